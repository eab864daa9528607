"""Image scores for held-out frames: BCE, IoU, Dice and the tip's position error.

Predictions are pixel probabilities in [0, 1]; truths are binary. IoU and Dice threshold the
prediction at 0.5 and are averaged over frames; BCE is the mean over every pixel (as the paper).
"""

import numpy as np

EPS = 1e-7


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
    """2 |P ∩ T| / (|P| + |T|) per frame; 1 where both are empty."""
    both, p, t = _overlaps(prob, truth)
    return np.where(p + t > 0, 2 * both / np.maximum(p + t, 1), 1.0)


def tip_pixels(frames: np.ndarray) -> np.ndarray:
    """(N, 2) pixel position [u, v] of the tip: the centroid of the lowest row of arm pixels (pixel
    centres); NaN for an empty frame."""
    binary = frames >= 0.5
    rows = binary.any(axis=2)                                   # (N, H): rows with arm pixels
    lowest = rows.shape[1] - 1 - np.argmax(rows[:, ::-1], axis=1)
    tip_row = binary[np.arange(len(frames)), lowest]            # (N, W)
    count = tip_row.sum(axis=1)
    u = (tip_row * np.arange(tip_row.shape[1])).sum(axis=1) / np.maximum(count, 1) + 0.5
    out = np.stack([u, lowest + 0.5], axis=1)
    out[~rows.any(axis=1)] = np.nan
    return out


def frame_scores(prob: np.ndarray, truth: np.ndarray, pixels_per_metre: float,
                 chunk: int = 1024) -> dict[str, np.ndarray]:
    """Per-frame BCE, IoU, Dice and tip error (mm, NaN where a frame is empty), computed chunk by chunk.

    Summaries over any subset of frames (blind, seeing, last 5 s) then cost nothing: see `summarise`.
    """
    parts: dict[str, list[np.ndarray]] = {"bce": [], "iou": [], "dice": [], "tip_mm": []}
    for start in range(0, len(prob), chunk):
        p, t = prob[start:start + chunk], truth[start:start + chunk]
        clipped = np.clip(p, EPS, 1 - EPS)
        parts["bce"].append(-np.log(np.where(t > 0, clipped, 1 - clipped)).mean(axis=(1, 2), dtype=np.float64))
        parts["iou"].append(iou_per_frame(p, t))
        parts["dice"].append(dice_per_frame(p, t))
        parts["tip_mm"].append(np.linalg.norm(tip_pixels(p) - tip_pixels(t), axis=1) / pixels_per_metre * 1e3)
    return {k: np.concatenate(v) for k, v in parts.items()}


def summarise(per_frame: dict[str, np.ndarray], mask: np.ndarray | None = None) -> dict[str, float]:
    """Means over the frames in mask (every frame has as many pixels, so the BCE mean is per pixel too)."""
    out = {}
    for key, values in per_frame.items():
        chosen = values if mask is None else values[mask]
        finite = chosen[np.isfinite(chosen)]
        out[key] = float(finite.mean()) if len(finite) else float("nan")
    return out


def image_scores(prob: np.ndarray, truth: np.ndarray, pixels_per_metre: float) -> dict[str, float]:
    """BCE, IoU, Dice and tip error (mm) averaged over all frames."""
    return summarise(frame_scores(prob, truth, pixels_per_metre))


def spearman(a: np.ndarray, b: np.ndarray) -> float:
    """Rank correlation, ties sharing their mean rank (NaN when either is constant)."""
    ra, rb = average_ranks(a), average_ranks(b)
    return float(np.corrcoef(ra, rb)[0, 1]) if ra.std() > 0 and rb.std() > 0 else float("nan")


def average_ranks(x: np.ndarray) -> np.ndarray:
    _, inverse, counts = np.unique(x, return_inverse=True, return_counts=True)
    first = np.concatenate([[0], np.cumsum(counts)[:-1]])
    return (first + (counts - 1) / 2)[inverse]
