"""How well a confidence ranks imagined frames by their true IoU, over every frame of the suite, with the value
each score would reach for a perfectly calibrated predictor of the same predicted spread.

Scores: Spearman(confidence, IoU); the AUROC of flagging frames whose IoU is below `FLAGGED` by low confidence;
the mean IoU of the `LEAST_TRUSTED` least-trusted frames against the rest's; and the sparsification curve
(the mean IoU of the frames kept as the least-trusted are dropped) beside the oracle's (dropping the worst
by true IoU), whose area between (AUSE) is 0 for a perfect ranking. Raw correlations have no fixed scale (Pernot
2024; Rasmussen et al. 2023), so each comes with a reference: the same score against the IoU a calibrated
predictor would see, its error drawn from its own predicted spread (`softarm.trust.confidence.Trust.reference_iou`).
"""

from typing import Any

import numpy as np

from softarm.model.metrics import average_ranks, spearman

LEAST_TRUSTED = 0.1            # share of frames the least-trusted figures single out
FLAGGED = 0.8                  # frames below this IoU are the ones a confidence should flag
FRACTIONS = np.linspace(0.0, 0.99, 100)  # shares of frames dropped along the sparsification curve


def trust_scores(confidence: np.ndarray, iou: np.ndarray) -> dict[str, Any]:
    """Every score of one confidence (M,) against the frames' IoU (M,)."""
    order = np.argsort(confidence, kind="stable")
    low = order[:max(1, round(len(order) * LEAST_TRUSTED))]
    rest = np.ones(len(order), bool)
    rest[low] = False
    curve, oracle = sparsification(confidence, iou), sparsification(iou, iou)
    return {"spearman": spearman(confidence, iou), "auroc": auroc(-confidence, iou < FLAGGED),
            "least_trusted_iou": float(iou[low].mean()),
            "rest_iou": float(iou[rest].mean()) if rest.any() else float("nan"),
            "ause": float(np.trapezoid(oracle - curve, FRACTIONS)), "sparsification": curve.tolist(),
            "oracle": oracle.tolist(), "flagged_share": float(np.mean(iou < FLAGGED)), "frames": int(len(iou))}


def sparsification(score: np.ndarray, iou: np.ndarray) -> np.ndarray:
    """(len(FRACTIONS),) the mean IoU of the frames kept when the lowest-scored share is dropped."""
    kept_sum = np.cumsum(iou[np.argsort(score, kind="stable")][::-1])[::-1]  # IoU summed over the frames from i on
    first = np.minimum((FRACTIONS * len(iou)).round().astype(int), len(iou) - 1)
    return kept_sum[first] / (len(iou) - first)


def auroc(score: np.ndarray, positive: np.ndarray) -> float:
    """The probability that a positive outscores a negative (ties half), by the Mann-Whitney rank sum; NaN
    without both."""
    n1 = int(positive.sum())
    n0 = len(positive) - n1
    if n1 == 0 or n0 == 0:
        return float("nan")
    ranks = average_ranks(score) + 1
    return float((ranks[positive].sum() - n1 * (n1 + 1) / 2) / (n1 * n0))


def with_reference(scores: dict[str, Any], reference: dict[str, Any]) -> dict[str, Any]:
    """A method's scores with its reference values beside the comparable ones."""
    keys = ("spearman", "auroc", "ause", "least_trusted_iou", "rest_iou")
    return {**scores, "reference": {k: reference[k] for k in keys}}
