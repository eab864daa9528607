"""`push`: a force on each of its nodes while active (docs/model.md). A poke is a short push, a steady wind a
long one."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import taichi as ti

from softarm.disturbances.kind import Disturbance, Params, drawn_row, mask, parameters
from softarm.disturbances.places import Places


@dataclass(frozen=True)
class Push(Disturbance):
    force: tuple[float, float]
    nodes: tuple[int, ...]
    kind = "push"
    keys = ("force", "nodes")
    drawn_by = ("rows", "force")

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Push":
        return cls(start, end, tuple(table.force), places.nodes(table.nodes, "nodes"))

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Push":
        """A poke of one row's nodes in a random direction, its magnitude in the spec's `force` range."""
        magnitude, angle = rng.uniform(*spec.force), rng.uniform(0, 2 * np.pi)
        force = (float(magnitude * np.cos(angle)), float(magnitude * np.sin(angle)))
        return cls(start, end, force, places.row(drawn_row(spec, rng)))

    def forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        out = np.zeros_like(x)
        out[list(self.nodes)] += np.array(self.force)
        return out

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return parameters(*self.force), mask(self.nodes, nodes), np.zeros(springs, np.int32)

    @staticmethod
    @ti.func
    def load_on_node(p: Params) -> ti.math.vec3:
        return ti.Vector([0.0, p[0], p[1]], ti.f64)
