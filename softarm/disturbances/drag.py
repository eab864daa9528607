"""`drag`: the arm in water, an octopus arm's home (docs/model.md). Every free node feels the fluid's drag toward
the current: with w = u - v its velocity relative to the water, F = (c + c2 |w|) w, a linear (Stokes) term and a
quadratic (form) term. A current is a steady drag; a gust is a short one."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import taichi as ti

from softarm.disturbances.kind import Disturbance, Params, parameters
from softarm.disturbances.places import Places

RELATIVE_SPEED = 1.0  # m/s: the speed of a node through the water assumed beside the current's, for the step's limit


@dataclass(frozen=True)
class Drag(Disturbance):
    velocity: tuple[float, float]
    coefficient: float
    quadratic: float
    kind = "drag"
    keys = ("velocity", "coefficient", "quadratic")
    optional = ("velocity", "quadratic")  # default: still water, no form drag
    drawn_by = ("speed", "coefficient")
    drawn_optional = ("quadratic",)

    @classmethod
    def from_table(cls, table: Any, start: float, end: Optional[float], places: Places) -> "Drag":
        velocity = (0.0, 0.0) if table.velocity is None else tuple(float(u) for u in table.velocity)
        quadratic = 0.0 if table.quadratic is None else float(table.quadratic)
        places.require(np.isfinite(velocity).all(), "velocity", list(velocity), "must be finite [ux, uy] (m/s)")
        places.require(table.coefficient >= 0, "coefficient", table.coefficient, "must be >= 0 (N s/m)")
        places.require(quadratic >= 0, "quadratic", quadratic, "must be >= 0 (N s^2/m^2)")
        return cls(start, end, velocity, float(table.coefficient), quadratic)

    @classmethod
    def draw(cls, spec: Any, rng: np.random.Generator, start: float, end: Optional[float], places: Places) -> "Drag":
        """A current in a random direction, its speed and coefficients in the spec's ranges."""
        speed, angle = rng.uniform(*spec.speed), rng.uniform(0, 2 * np.pi)
        velocity = (float(speed * np.cos(angle)), float(speed * np.sin(angle)))
        quadratic = float(rng.uniform(*spec.quadratic)) if spec.quadratic is not None else 0.0
        return cls(start, end, velocity, float(rng.uniform(*spec.coefficient)), quadratic)

    def forces(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        w = np.array(self.velocity) - v
        speed = np.sqrt(w[:, 0] ** 2 + w[:, 1] ** 2)
        return (self.coefficient + self.quadratic * speed)[:, None] * w

    def stability(self) -> tuple[float, float]:
        """The drag damps a node toward the water: dF/dv is c + 2 c2 |w| at most, counted at |w| = |u| + 1 m/s."""
        return 0.0, self.coefficient + 2 * self.quadratic * (float(np.hypot(*self.velocity)) + RELATIVE_SPEED)

    def slot(self, nodes: int, springs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        params = parameters(*self.velocity, self.coefficient, self.quadratic)
        return params, np.zeros(nodes, np.int32), np.zeros(springs, np.int32)

    @staticmethod
    @ti.func
    def force_on_free_node(p: Params, x: ti.math.vec2, v: ti.math.vec2) -> ti.math.vec2:
        """(c + c2 |w|) w with w = u - v (current p[0], p[1], c p[2], c2 p[3])."""
        w = ti.Vector([p[0], p[1]], ti.f64) - v
        return (p[2] + p[3] * ti.sqrt(w[0] * w[0] + w[1] * w[1])) * w
