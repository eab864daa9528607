"""The privileged baseline: a ridge map from the last 2 s of inputs to every node's position, drawn through the
recording's own camera. Privileged because it is fitted on node positions, which a real robot never has: the
bar a learned body image should clear, beside the ridge to the latent code that shares its information.

Frame k is answered from the normalised inputs of samples k - lead - HISTORY + 1 .. k - lead; samples before
the first are the training mean (0 once normalised), so it answers for every frame the latent model does.
"""

from typing import Optional, Sequence

import numpy as np

from softarm.config import CameraConfig

HISTORY = 200     # samples: 2 s at the default frame rate
STRIDE = 4        # training frames between two fitted targets: the fit's cost, not its quality, shrinks
ALPHA = 1e-3      # L2 penalty per target, as the latent ridge's
CHUNK = 2048      # targets per block of the normal equations

NodeRidge = tuple[np.ndarray, np.ndarray]  # (weights (HISTORY * F, 2N), bias (2N,))


def windows(normalised: np.ndarray, frames: np.ndarray, lead: int) -> np.ndarray:
    """(M, HISTORY * F) float64: the flattened input window of each frame index, zero-padded before the start."""
    padded = np.concatenate([np.zeros((HISTORY, normalised.shape[1])), normalised])
    last = frames - lead + HISTORY  # index of the window's last sample in `padded`
    return padded[last[:, None] - np.arange(HISTORY - 1, -1, -1)].reshape(len(frames), -1)


def fit(series: Sequence[tuple[np.ndarray, np.ndarray, int]], lead: int) -> Optional[NodeRidge]:
    """Least squares with an L2 penalty from windows to positions, over every STRIDE-th training frame of each
    (normalised inputs (T, F), positions (T, N, 2), train_end); the normal equations are summed block by block,
    so memory stays that of one block whatever the corpus."""
    targets = [(x, p, np.arange(lead, end, STRIDE)) for x, p, end in series if end > lead]
    count = sum(len(k) for _, _, k in targets)
    if not count:
        return None
    features, outputs = HISTORY * targets[0][0].shape[1], targets[0][1][0].size
    sum_x, sum_y = np.zeros(features), np.zeros(outputs)
    xx, xy = np.zeros((features, features)), np.zeros((features, outputs))
    for x, p, frames in targets:
        for first in range(0, len(frames), CHUNK):
            block = frames[first:first + CHUNK]
            w, y = windows(x, block, lead), p[block].reshape(len(block), -1).astype(np.float64)
            sum_x += w.sum(0)
            sum_y += y.sum(0)
            xx += w.T @ w
            xy += w.T @ y
    mean_x, mean_y = sum_x / count, sum_y / count
    xx -= count * np.outer(mean_x, mean_x)
    xy -= count * np.outer(mean_x, mean_y)
    weights = np.linalg.solve(xx + ALPHA * count * np.eye(features), xy)
    return weights, mean_y - mean_x @ weights


def predict(model: NodeRidge, normalised: np.ndarray, frames: np.ndarray, lead: int) -> np.ndarray:
    """(M, N, 2) node positions of the frames, from the normalised inputs (T, F)."""
    weights, bias = model
    out = np.concatenate([windows(normalised, frames[i:i + CHUNK], lead) @ weights + bias
                          for i in range(0, len(frames), CHUNK)])
    return out.reshape(len(frames), -1, 2)


def draw(positions: np.ndarray, camera: CameraConfig, outline: np.ndarray) -> np.ndarray:
    """(M, H, W) binary frames of node positions (M, N, 2), by softarm's own rasteriser (the camera's rule)."""
    from softarm.sim.raster import Rasteriser  # Taichi only when this baseline is scored
    from softarm.sim.runtime import ensure_taichi

    ensure_taichi()
    rasteriser = Rasteriser(camera, outline, 1, min(len(positions), CHUNK))
    return np.concatenate([rasteriser.render(positions[None, i:i + CHUNK], len(positions[i:i + CHUNK]))[0].copy()
                           for i in range(0, len(positions), CHUNK)])
