"""Bend sensors: a flexible strip glued along the arm reads how much the arm curves beneath it (the flex and
curvature sensors soft robots carry). A sensor is a node triple [a, m, b] along the arm; it reads the signed angle
by which the direction from m to b turns from the direction from a to m, less the same angle at rest, in radians,
positive counter-clockwise (y up): the arm's curvature integrated between a and b. docs/model.md, Sensors.
"""

from typing import Any, Sequence

import numpy as np

from softarm.errors import ConfigError
from softarm.sensors.kind import SensorKind


def turning(positions: np.ndarray, triples: np.ndarray) -> np.ndarray:
    """(..., S) the signed angle from (x_m - x_a) to (x_b - x_m), rad in (-pi, pi], for positions (..., N, 2)."""
    a, m, b = (positions[..., triples[:, i], :] for i in range(3))
    u, v = m - a, b - m
    cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    return np.arctan2(cross, (u * v).sum(axis=-1))


class Bend(SensorKind):
    name = "bend"
    topic = "/arm/bend"
    field = "bend"
    unit = "rad"
    width = 3
    title = "softarm.Bend"
    description = "Bend sensor readings: the turn of the arm between a sensor's first and last node, less at rest"

    def check(self, placements: Sequence[Sequence[int]], nodes: int, key: str) -> np.ndarray:
        triples = np.asarray(placements, np.int64)
        if triples.size == 0:
            return triples.reshape(0, 3)
        if triples.ndim != 2 or triples.shape[1] != 3:
            raise ConfigError(f"{key} must be a list of [a, m, b] node triples, not an array of shape {triples.shape}")
        for k, triple in enumerate(triples.tolist()):
            if not all(0 <= node < nodes for node in triple):
                raise ConfigError(f"{key}[{k}] = {triple} names a node outside the arm's 0..{nodes - 1}")
            if len(set(triple)) != 3:
                raise ConfigError(f"{key}[{k}] = {triple}: a bend sensor needs three different nodes")
        return triples

    def ideal(self, positions: np.ndarray, rest: np.ndarray, placements: np.ndarray) -> np.ndarray:
        turned = (turning(np.asarray(positions, np.float64), placements)
                  - turning(np.asarray(rest, np.float64), placements))
        wrapped = np.remainder(turned + np.pi, 2 * np.pi) - np.pi  # a turn past the straight-back angle, back in range
        return np.where(np.abs(turned) > np.pi, wrapped, turned)

    def imperfect(self, ideal: np.ndarray, sensing: Any, stream: int) -> np.ndarray:
        """White noise of `sensing.bend_noise` rad a sample, seeded by [sensing] seed and the recording's stream."""
        noise = sensing.bend_noise or 0.0
        if noise <= 0.0:
            return ideal
        rng = np.random.default_rng([sensing.seed, stream, 1])  # 1: not the stretch's stream
        return ideal + rng.normal(0.0, noise, ideal.shape)
