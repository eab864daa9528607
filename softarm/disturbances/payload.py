"""`payload`: extra mass on each of its nodes while active, in their inertia and their weight (docs/model.md). A
grasped object is a payload on the tip row."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import taichi as ti

from softarm.disturbances.kind import Disturbance, Params, drawn_row, mask, parameters
from softarm.disturbances.places import Places


@dataclass(frozen=True)
class Payload(Disturbance):
    mass: float
    nodes: tuple[int, ...]
    kind = "payload"
    keys = ("mass", "nodes")
    drawn_by = ("rows", "mass")

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Payload":
        places.require(table.mass >= 0, "mass", table.mass, "must be >= 0 (kg)")
        return cls(start, end, float(table.mass), places.nodes(table.nodes, "nodes"))

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Payload":
        """A load on one row's nodes (a grasped object on the tip row)."""
        return cls(start, end, float(rng.uniform(*spec.mass)), places.row(drawn_row(spec, rng)))

    def extra_mass(self, nodes: int) -> np.ndarray:
        return self.mass * mask(self.nodes, nodes).astype(float)

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return parameters(self.mass), mask(self.nodes, nodes), np.zeros(springs, np.int32)

    @staticmethod
    @ti.func
    def load_on_node(p: Params) -> ti.math.vec3:
        return ti.Vector([p[0], 0.0, 0.0], ti.f64)
