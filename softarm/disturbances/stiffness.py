"""`stiffness`: each of its springs' stiffness multiplied by a factor while active, rest length and damper unchanged
(docs/model.md); below 1 is damage or fatigue, above 1 stiffening."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import taichi as ti

from softarm.disturbances.kind import Disturbance, Params, drawn_row, mask, parameters
from softarm.disturbances.places import Places


@dataclass(frozen=True)
class Stiffness(Disturbance):
    factor: float
    springs: tuple[int, ...]
    kind = "stiffness"
    keys = ("factor", "springs")
    drawn_by = ("rows", "factor")
    drawn_optional = ("span",)

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Stiffness":
        places.require(table.factor > 0, "factor", table.factor, "must be > 0 (below 1: damage, above 1: stiffening)")
        return cls(start, end, float(table.factor), places.springs(table.springs, "springs"))

    @classmethod
    def check_spec(cls, spec: Any, places: Places) -> None:
        places.require(spec.factor[0] > 0, "factor", list(spec.factor), "factors must be > 0")
        places.segment(spec.rows[1], spec.span or 2)

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float],
             places: Places) -> "Stiffness":
        """Every spring of a segment `span` rows long, from a random row."""
        first = drawn_row(spec, rng)
        return cls(start, end, float(rng.uniform(*spec.factor)), places.segment(first, spec.span or 2))

    def stiffness_factor(self, springs: int) -> np.ndarray:
        return np.where(mask(self.springs, springs) > 0, self.factor, 1.0)

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return parameters(self.factor), np.zeros(nodes, np.int32), mask(self.springs, springs)

    @staticmethod
    @ti.func
    def factor_on_spring(p: Params) -> ti.f64:
        return p[0]
