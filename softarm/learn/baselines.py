"""Trivial answers that every imagination is judged against: the mean frame and a ridge regression.

A model is only worth its training if it beats predicting the average training frame, and a linear
map from the same stretch window to the same latent code.
"""

import numpy as np


def ridge_fit(inputs: np.ndarray, targets: np.ndarray, alpha: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Least squares with an L2 penalty, from flattened inputs (M, ...) to targets (M, K): (weights, bias)."""
    x = inputs.reshape(len(inputs), -1).astype(np.float64)
    mean_x, mean_y = x.mean(0), targets.mean(0)
    xc, yc = x - mean_x, targets - mean_y
    weights = np.linalg.solve(xc.T @ xc + alpha * len(x) * np.eye(x.shape[1]), xc.T @ yc)
    return weights, mean_y - mean_x @ weights


def ridge_predict(model: tuple[np.ndarray, np.ndarray], inputs: np.ndarray) -> np.ndarray:
    """Targets (M, K) predicted for flattened inputs (M, ...) by a `ridge_fit` model."""
    weights, bias = model
    return inputs.reshape(len(inputs), -1) @ weights + bias
