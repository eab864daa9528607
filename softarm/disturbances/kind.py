"""What every disturbance kind is (docs/model.md, Disturbances): its interval, its parameters under the names the
model document gives them, its effect in NumPy for the reference, and the same effect as Taichi code for the
simulator's kernel, side by side in the kind's own module so that one place says what the kind does.

A kind acts in one or more of three ways, each a NumPy method and a kernel hook that must agree:
- a load on its nodes (extra mass, a constant force): `extra_mass` / `forces` and `load_on_node`;
- a factor on its springs' stiffness: `stiffness_factor` and `factor_on_spring`;
- a force on every free node from that node's state: `forces` and `force_on_free_node`.
The simulator reads each disturbance packed into a slot: its parameters (`slot`, at most PARAMETERS floats, which
the hooks read as `p`) and masks of the nodes and springs it touches.
"""

from dataclasses import dataclass
from typing import Any, Callable, ClassVar, Optional

import numpy as np
import taichi as ti

from softarm.disturbances.places import Places

PARAMETERS = 6  # floats a simulator slot holds
Params = ti.types.vector(PARAMETERS, ti.f64)  # a slot's parameters, as the kernel hooks read them


@dataclass(frozen=True)
class Disturbance:
    start: float
    end: Optional[float]  # None: to the end of the run

    kind: ClassVar[str]
    keys: ClassVar[tuple[str, ...]]              # the parameters a [[disturbances]] table of this kind gives
    optional: ClassVar[tuple[str, ...]] = ()     # those of `keys` a table may leave out (the kind has a default)
    drawn_by: ClassVar[tuple[str, ...]] = ()     # the [[world.random]] keys, beside count and start, it needs
    drawn_optional: ClassVar[tuple[str, ...]] = ()  # and those it may take

    # Kernel hooks (ti.func, as staticmethods), None where the kind does not act that way; `p` is the slot's
    # parameters. load_on_node(p) -> (extra mass, Fx, Fy) on each node of its mask; factor_on_spring(p) ->
    # stiffness factor on each spring of its mask; force_on_free_node(p, x, v) -> (Fx, Fy) on every free node.
    load_on_node: ClassVar[Optional[Callable[..., Any]]] = None
    factor_on_spring: ClassVar[Optional[Callable[..., Any]]] = None
    force_on_free_node: ClassVar[Optional[Callable[..., Any]]] = None

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Disturbance":
        """One [[disturbances]] table (its keys checked by `places`)."""
        raise NotImplementedError

    @classmethod
    def check_spec(cls, spec: Any, places: Places) -> None:
        """What a [[world.random]] spec of this kind must hold beyond [min, max] ranges (none by default)."""

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float],
             places: Places) -> "Disturbance":
        """One of this kind drawn by a [[world.random]] spec, with its interval already drawn."""
        raise NotImplementedError

    def active(self, t: float) -> bool:
        return self.start <= t and (self.end is None or t < self.end)

    def metadata(self) -> dict[str, Any]:
        """The recording's entry: kind, start, end (None: to the end) and every parameter resolved, so that
        another program can re-simulate the run."""
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

    def stability(self) -> tuple[float, float]:
        """(stiffness N/m, damping N s/m) it may add between a free node and a fixed point at its stiffest, for
        the stability limit of the step (statics.max_stable_substep); stiffened springs count apart."""
        return 0.0, 0.0

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(PARAMETERS,) parameters, (N,) nodes and (S,) springs it touches, as the simulator reads them."""
        return np.zeros(PARAMETERS), np.zeros(nodes, np.int32), np.zeros(springs, np.int32)


def drawn_row(spec: Any, rng: np.random.Generator) -> int:
    """A row drawn from a [[world.random]] spec's inclusive `rows` range."""
    return int(rng.integers(spec.rows[0], spec.rows[1] + 1))


def mask(indices: tuple[int, ...], count: int) -> np.ndarray:
    out = np.zeros(count, np.int32)
    out[list(indices)] = 1
    return out


def parameters(*values: float) -> np.ndarray:
    """A slot's parameters: the given values, zeros after them."""
    out = np.zeros(PARAMETERS)
    out[:len(values)] = values
    return out
