"""`obstacle`: a fixed rigid disc; every free node inside it feels a penalty contact force along the outward normal,
never pulling (docs/model.md). A wall is a disc with a large radius."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import taichi as ti

from softarm.disturbances.kind import Disturbance, Params, drawn_row, parameters
from softarm.disturbances.places import Places


@dataclass(frozen=True)
class Obstacle(Disturbance):
    centre: tuple[float, float]
    radius: float
    stiffness: float
    damping: float
    kind = "obstacle"
    keys = ("centre", "radius", "stiffness", "damping")
    optional = ("stiffness", "damping")  # default: [world] contact_*
    drawn_by = ("rows", "radius", "gap")

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
    def check_spec(cls, spec: Any, places: Places) -> None:
        places.require(spec.radius[0] > 0, "radius", list(spec.radius), "radii must be > 0")

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float],
             places: Places) -> "Obstacle":
        """A disc beside a row, `gap` from the arm's resting edge there, on a random side: the swing meets it."""
        row, side = drawn_row(spec, rng), 1 if rng.random() < 0.5 else -1
        radius, gap = float(rng.uniform(*spec.radius)), float(rng.uniform(*spec.gap))
        edge = places.edge(row, side)
        centre = (float(edge[0] + side * (gap + radius)), float(edge[1]))
        world = places.world
        return cls(start, end, centre, radius, world.contact_stiffness, world.contact_damping)

    def forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        d = x - np.array(self.centre)
        distance = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2)
        inside = (distance < self.radius) & (distance > 0)
        out = np.zeros_like(x)
        n = d[inside] / distance[inside, None]
        depth = self.radius - distance[inside]
        magnitude = np.maximum(0.0, self.stiffness * depth - self.damping * (v[inside] * n).sum(axis=1))
        out[inside] = magnitude[:, None] * n
        return out

    def stability(self) -> tuple[float, float]:
        return self.stiffness, self.damping

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        params = parameters(*self.centre, self.radius, self.stiffness, self.damping)
        return params, np.zeros(nodes, np.int32), np.zeros(springs, np.int32)

    def encloses(self, points: np.ndarray) -> np.ndarray:
        """Which points lie inside the disc (|x - centre| < radius): where it touches the body."""
        d = points - np.array(self.centre)
        return np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2) < self.radius

    @staticmethod
    @ti.func
    def force_on_free_node(p: Params, x: ti.math.vec2, v: ti.math.vec2) -> ti.math.vec2:
        """max(0, k_c depth - b_c v.n) n inside the disc (centre p[0], p[1], radius p[2], k_c p[3], b_c p[4])."""
        f = ti.Vector([0.0, 0.0], ti.f64)
        offset = x - ti.Vector([p[0], p[1]], ti.f64)
        distance = ti.sqrt(offset[0] * offset[0] + offset[1] * offset[1])
        if 0.0 < distance < p[2]:
            n = offset * (1.0 / distance)
            f = ti.max(0.0, p[3] * (p[2] - distance) - p[4] * v.dot(n)) * n
        return f
