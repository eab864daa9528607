"""The world acting on the body (docs/model.md, Disturbances): one class per kind, named in KINDS.

Each kind says what it adds at a time it is active (start <= t < end): forces on nodes (`forces`), mass on
nodes (`extra_mass`), a factor on spring stiffnesses (`stiffness_factor`); the NumPy reference sums them,
and the simulator reads each disturbance packed into a slot (`slot`: a code, the parameters, the nodes and
springs it touches). `metadata` is the recording's entry: kind, start, end (None: to the end of the run)
and the parameters exactly as docs/model.md names them, so another program can re-simulate the run.
"""

from dataclasses import dataclass
from typing import Any, ClassVar, Optional

import numpy as np

from softarm.arm.places import Places

PARAMETERS = 6  # floats a simulator slot holds


@dataclass(frozen=True)
class Disturbance:
    start: float
    end: Optional[float]  # None: to the end of the run

    kind: ClassVar[str]
    code: ClassVar[int]   # the simulator's kind code
    keys: ClassVar[tuple[str, ...]]  # the parameters a [[disturbances]] table of this kind gives

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Disturbance":
        """One [[disturbances]] table (its keys checked by `places`)."""
        raise NotImplementedError

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Disturbance":
        """One of this kind drawn by a [[world.random]] spec, with its interval already drawn."""
        raise NotImplementedError

    def active(self, t: float) -> bool:
        return self.start <= t and (self.end is None or t < self.end)

    def metadata(self) -> dict[str, Any]:
        return {"kind": self.kind, "start": self.start, "end": self.end, **self.parameters()}

    def parameters(self) -> dict[str, Any]:
        """The kind's parameters under the names `keys` gives them (docs/model.md), tuples as lists."""
        values = {key: getattr(self, key) for key in self.keys}
        return {key: list(v) if isinstance(v, tuple) else v for key, v in values.items()}

    def forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(N, 2) N on every node while active, from the state (x, v)."""
        return np.zeros_like(x)

    def extra_mass(self, nodes: int) -> np.ndarray:
        """(N,) kg added to every node while active."""
        return np.zeros(nodes)

    def stiffness_factor(self, springs: int) -> np.ndarray:
        """(S,) factor on every spring's stiffness while active."""
        return np.ones(springs)

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(PARAMETERS,) parameters, (N,) nodes and (S,) springs it touches, as the simulator reads them."""
        return np.zeros(PARAMETERS), np.zeros(nodes, np.int32), np.zeros(springs, np.int32)


def _row(spec: Any, rng: np.random.Generator) -> int:
    """A row drawn from a [[world.random]] spec's inclusive `rows` range."""
    return int(rng.integers(spec.rows[0], spec.rows[1] + 1))


def _mask(indices: tuple[int, ...], count: int) -> np.ndarray:
    mask = np.zeros(count, np.int32)
    mask[list(indices)] = 1
    return mask


@dataclass(frozen=True)
class Push(Disturbance):
    force: tuple[float, float]
    nodes: tuple[int, ...]
    kind = "push"
    code = 0
    keys = ("force", "nodes")

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Push":
        return cls(start, end, tuple(table.force), places.nodes(table.nodes, "nodes"))

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Push":
        """A poke of one row's nodes in a random direction."""
        magnitude, angle = rng.uniform(*spec.force), rng.uniform(0, 2 * np.pi)
        force = (float(magnitude * np.cos(angle)), float(magnitude * np.sin(angle)))
        return cls(start, end, force, places.row(_row(spec, rng)))

    def forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        out = np.zeros_like(x)
        out[list(self.nodes)] += np.array(self.force)
        return out

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (np.array([*self.force, 0, 0, 0, 0], float), _mask(self.nodes, nodes), np.zeros(springs, np.int32))


@dataclass(frozen=True)
class Payload(Disturbance):
    mass: float
    nodes: tuple[int, ...]
    kind = "payload"
    code = 1
    keys = ("mass", "nodes")

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Payload":
        places.require(table.mass >= 0, "mass", table.mass, "must be >= 0 (kg)")
        return cls(start, end, float(table.mass), places.nodes(table.nodes, "nodes"))

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Payload":
        """A load on one row's nodes (a grasped object on the tip row)."""
        return cls(start, end, float(rng.uniform(*spec.mass)), places.row(_row(spec, rng)))

    def extra_mass(self, nodes: int) -> np.ndarray:
        return self.mass * _mask(self.nodes, nodes).astype(float)

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return np.array([self.mass, 0, 0, 0, 0, 0], float), _mask(self.nodes, nodes), np.zeros(springs, np.int32)


@dataclass(frozen=True)
class Stiffness(Disturbance):
    factor: float
    springs: tuple[int, ...]
    kind = "stiffness"
    code = 2
    keys = ("factor", "springs")

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Stiffness":
        places.require(table.factor > 0, "factor", table.factor, "must be > 0 (below 1: damage, above 1: stiffening)")
        return cls(start, end, float(table.factor), places.springs(table.springs, "springs"))

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Stiffness":
        """Every spring of a segment `span` rows long, from a random row."""
        first = _row(spec, rng)
        return cls(start, end, float(rng.uniform(*spec.factor)), places.segment(first, spec.span or 2))

    def stiffness_factor(self, springs: int) -> np.ndarray:
        return np.where(_mask(self.springs, springs) > 0, self.factor, 1.0)

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return np.array([self.factor, 0, 0, 0, 0, 0], float), np.zeros(nodes, np.int32), _mask(self.springs, springs)


@dataclass(frozen=True)
class Obstacle(Disturbance):
    centre: tuple[float, float]
    radius: float
    stiffness: float
    damping: float
    kind = "obstacle"
    code = 3
    keys = ("centre", "radius", "stiffness", "damping")

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Obstacle":
        places.require(table.radius > 0, "radius", table.radius, "must be > 0 (m)")
        stiffness = places.world.contact_stiffness if table.stiffness is None else table.stiffness
        damping = places.world.contact_damping if table.damping is None else table.damping
        places.require(stiffness > 0, "stiffness", stiffness, "must be > 0 (N/m)")
        places.require(damping >= 0, "damping", damping, "must be >= 0 (N s/m)")
        obstacle = cls(start, end, tuple(table.centre), float(table.radius), float(stiffness), float(damping))
        places.require(not obstacle.encloses(places.driven()).any(), "centre", list(table.centre),
                       "the disc encloses a driven node (the top row): move it or shrink it")
        return obstacle

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Obstacle":
        """A disc beside a row, `gap` from the arm's resting edge there, on a random side: the swing meets it."""
        row, side = _row(spec, rng), 1 if rng.random() < 0.5 else -1
        radius, gap = float(rng.uniform(*spec.radius)), float(rng.uniform(*spec.gap))
        edge = places.edge(row, side)
        centre = (float(edge[0] + side * (gap + radius)), float(edge[1]))
        world = places.world
        return cls(start, end, centre, radius, world.contact_stiffness, world.contact_damping)

    def forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Penalty contact on every node inside the disc, along the outward normal (never pulling)."""
        d = x - np.array(self.centre)
        distance = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2)
        inside = (distance < self.radius) & (distance > 0)
        out = np.zeros_like(x)
        n = d[inside] / distance[inside, None]
        depth = self.radius - distance[inside]
        magnitude = np.maximum(0.0, self.stiffness * depth - self.damping * (v[inside] * n).sum(axis=1))
        out[inside] = magnitude[:, None] * n
        return out

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        params = np.array([*self.centre, self.radius, self.stiffness, self.damping, 0], float)
        return params, np.zeros(nodes, np.int32), np.zeros(springs, np.int32)

    def encloses(self, points: np.ndarray) -> np.ndarray:
        d = points - np.array(self.centre)
        return np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2) < self.radius


KINDS: dict[str, type[Disturbance]] = {k.kind: k for k in (Push, Payload, Stiffness, Obstacle)}
