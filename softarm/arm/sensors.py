"""Stretch sensors (docs/model.md, Sensors): change of distance between two nodes, in metres."""

import numpy as np


def stretch(positions: np.ndarray, rest: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(..., P) readings |x_a - x_b| - |x_a,rest - x_b,rest| for positions of shape (..., N, 2)."""
    a, b = pairs[:, 0], pairs[:, 1]
    now = np.linalg.norm(positions[..., a, :] - positions[..., b, :], axis=-1)
    return now - np.linalg.norm(rest[a] - rest[b], axis=-1)
