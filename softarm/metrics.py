"""Image scores for held-out frames: BCE, IoU, Dice and the tip's position error, plus a ridge baseline.

Predictions are pixel probabilities in [0, 1]; truths are binary. IoU and Dice threshold the
prediction at 0.5 and are averaged over frames; BCE is the mean over every pixel (as the paper).
"""

import numpy as np

EPS = 1e-7


def bce(prob: np.ndarray, truth: np.ndarray) -> float:
    p = np.clip(prob.astype(np.float64), EPS, 1 - EPS)
    t = truth.astype(np.float64)
    return float(-np.mean(t * np.log(p) + (1 - t) * np.log(1 - p)))


def _overlaps(prob: np.ndarray, truth: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    pred, true = prob >= 0.5, truth > 0
    axes = tuple(range(1, pred.ndim))
    return (pred & true).sum(axes), pred.sum(axes), true.sum(axes)


def iou_per_frame(prob: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """|P ∩ T| / |P ∪ T| per frame; 1 where both are empty."""
    both, p, t = _overlaps(prob, truth)
    union = p + t - both
    return np.where(union > 0, both / np.maximum(union, 1), 1.0)


def dice_per_frame(prob: np.ndarray, truth: np.ndarray) -> np.ndarray:
    both, p, t = _overlaps(prob, truth)
    return np.where(p + t > 0, 2 * both / np.maximum(p + t, 1), 1.0)


def tip_pixels(frames: np.ndarray) -> np.ndarray:
    """(N, 2) pixel position [u, v] of the tip: the centroid of the lowest row of arm pixels (pixel
    centres); NaN for an empty frame."""
    binary = frames >= 0.5
    out = np.full((len(frames), 2), np.nan)
    rows = binary.any(axis=2)
    for n in np.flatnonzero(rows.any(axis=1)):
        r = np.flatnonzero(rows[n])[-1]
        out[n] = np.flatnonzero(binary[n, r]).mean() + 0.5, r + 0.5
    return out


def tip_error_mm(prob: np.ndarray, truth: np.ndarray, pixels_per_metre: float) -> float:
    """Mean distance between predicted and true tips, mm (frames where either is empty are skipped)."""
    d = np.linalg.norm(tip_pixels(prob) - tip_pixels(truth), axis=1)
    d = d[np.isfinite(d)]
    return float(np.mean(d) / pixels_per_metre * 1e3) if len(d) else float("nan")


def image_scores(prob: np.ndarray, truth: np.ndarray, pixels_per_metre: float) -> dict[str, float]:
    return {"bce": bce(prob, truth), "iou": float(iou_per_frame(prob, truth).mean()),
            "dice": float(dice_per_frame(prob, truth).mean()),
            "tip_mm": tip_error_mm(prob, truth, pixels_per_metre)}


def ridge_fit(inputs: np.ndarray, targets: np.ndarray, alpha: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Least squares with an L2 penalty, from flattened inputs (M, ...) to targets (M, K): (weights, bias)."""
    x = inputs.reshape(len(inputs), -1).astype(np.float64)
    mean_x, mean_y = x.mean(0), targets.mean(0)
    xc, yc = x - mean_x, targets - mean_y
    weights = np.linalg.solve(xc.T @ xc + alpha * len(x) * np.eye(x.shape[1]), xc.T @ yc)
    return weights, mean_y - mean_x @ weights


def ridge_predict(model: tuple[np.ndarray, np.ndarray], inputs: np.ndarray) -> np.ndarray:
    weights, bias = model
    return inputs.reshape(len(inputs), -1) @ weights + bias
