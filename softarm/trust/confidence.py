"""How far to trust an imagined frame: each way of measuring it is one class, named in `registry.TRUST`.

`train.confidence` picks the checkpoint's; `softarm evaluate` scores every way a checkpoint can answer, so they
are compared on the same frames. Every confidence is in (0, 1], higher is surer. Each way also says what a
perfectly calibrated predictor with its own predicted spread would see (`reference_iou`): the yardstick of
its scores (`softarm.trust.scoring`).
"""

from typing import Any, Callable, ClassVar, Optional

import numpy as np

from softarm.model.metrics import iou_per_frame
from softarm.model.prediction import Prediction

Decode = Callable[[np.ndarray], np.ndarray]  # normalised latents (M, K) -> pixel probabilities (M, H, W)


class Trust:
    name: ClassVar[str]

    @classmethod
    def build(cls, calibration: Optional[dict[str, Any]]) -> Optional["Trust"]:
        """This way for a checkpoint with `calibration` (its `calibration` state, None if it has none); None
        where the checkpoint cannot answer it."""
        return cls()

    def available(self, prediction: Prediction) -> bool:
        return True

    def confidence(self, prediction: Prediction) -> np.ndarray:
        """(M,) in (0, 1]."""
        raise NotImplementedError

    def variance(self, prediction: Prediction) -> np.ndarray:
        """(M, K) the spread of the normalised latent this way predicts."""
        raise NotImplementedError

    def reference_iou(self, prediction: Prediction, answer: np.ndarray, decode: Decode,
                      rng: np.random.Generator) -> np.ndarray:
        """(M,) the IoU a calibrated predictor with this spread would score: the truth drawn as the answer plus an
        error from the predicted variance, drawn through the decoder; `answer` (M, H, W) is the prediction's
        latents decoded (every way shares it)."""
        truth = prediction.latents + rng.standard_normal(prediction.latents.shape) * np.sqrt(self.variance(prediction))
        return iou_per_frame(answer, decode(truth) >= 0.5)


class ErrorHeadTrust(Trust):
    """The error head: a network on the recurrent state that learned the model's own squared errors."""
    name = "error_head"

    def confidence(self, prediction: Prediction) -> np.ndarray:
        return prediction.confidence

    def variance(self, prediction: Prediction) -> np.ndarray:
        return np.exp(prediction.log_error)


class EnsembleTrust(Trust):
    """A deep ensemble's disagreement: the variance of its members' latents, 1 / (1 + its mean)."""
    name = "ensemble"

    def available(self, prediction: Prediction) -> bool:
        return prediction.spread is not None

    def confidence(self, prediction: Prediction) -> np.ndarray:
        return 1.0 / (1.0 + self.variance(prediction).mean(axis=1))

    def variance(self, prediction: Prediction) -> np.ndarray:
        if prediction.spread is None:
            raise ValueError("ensemble confidence needs a checkpoint with ensemble members (train.ensemble > 1)")
        return prediction.spread


class CalibratedTrust(Trust):
    """The frame's IoU predicted from what the model knows without a camera: the error head's predicted error,
    the surprise and the felt residual, how far the latent strays from the ridge baseline's answer to the same
    window and what the decoder draws of it, its doubt and the arm's area (where the calibration was fitted
    with them), and the members' disagreement where there is an ensemble; a linear map of their logarithms to
    log(1 - IoU + MARGIN), fitted on held-out frames when the checkpoint was trained (`calibration`)."""
    name = "calibrated"
    MARGIN = 0.01

    def __init__(self, weights: np.ndarray, spread: float, ridge_gap: bool = False, picture: bool = False):
        self.weights = weights  # (features + 1,): the map, constant last
        self.spread = spread    # the residual's standard deviation on the frames it was fitted on
        self.ridge_gap = ridge_gap  # whether the ridge gap is a feature (checkpoints before it: not)
        self.picture = picture      # whether the decoded frame's doubt and area are (checkpoints before them: not)

    @classmethod
    def build(cls, calibration: Optional[dict[str, Any]]) -> Optional["Trust"]:
        if not calibration:
            return None
        return cls(np.asarray(calibration["weights"], np.float64), float(calibration["spread"]),
                   bool(calibration.get("ridge_gap", False)), bool(calibration.get("picture", False)))

    def available(self, prediction: Prediction) -> bool:
        return ((prediction.ridge_gap is not None or not self.ridge_gap)
                and (prediction.picture is not None or not self.picture)
                and len(self.weights) == len(calibration_features(prediction, self.ridge_gap, self.picture)) + 1)

    def predicted(self, prediction: Prediction) -> np.ndarray:
        """(M,) the predicted log(1 - IoU + MARGIN)."""
        features = calibration_features(prediction, self.ridge_gap, self.picture)
        return np.column_stack([*features, np.ones(len(prediction.latents))]) @ self.weights

    def confidence(self, prediction: Prediction) -> np.ndarray:
        return as_iou(self.predicted(prediction))

    def reference_iou(self, prediction: Prediction, answer: np.ndarray, decode: Decode,
                      rng: np.random.Generator) -> np.ndarray:
        """The IoU drawn from this way's own predicted distribution: its residual spread around its prediction."""
        return np.clip(1.0 + self.MARGIN - np.exp(self.predicted(prediction) + self.spread * rng.standard_normal(
            len(prediction.latents))), 0.0, 1.0)


RIDGE_FLOOR = 1e-3  # added to the ridge gap (normalised latent units squared) before its logarithm
PICTURE_FLOOR = 1.0  # added to the decoded frame's doubt (nats) and area (pixels) before their logarithms


def as_iou(predicted: np.ndarray) -> np.ndarray:
    """A predicted log(1 - IoU + MARGIN) as a confidence in (0, 1]."""
    return np.clip(1.0 + CalibratedTrust.MARGIN - np.exp(predicted), 1e-3, 1.0)


def calibration_features(prediction: Prediction, ridge_gap: bool, picture: bool = False) -> list[np.ndarray]:
    """log of the error head's mean predicted squared error, of the surprise and of the felt residual (each +0.1;
    1 where unknown), with `ridge_gap` of the gap to the ridge's latent (+1e-3), with `picture` of the decoded
    frame's doubt and area (each +1), and of the members' mean variance where there are members."""
    features = [np.log(np.exp(prediction.log_error).mean(axis=1))]
    for felt in (prediction.surprise, prediction.residual):
        felt = felt if felt is not None else np.ones(len(prediction.latents))
        features.append(np.log(np.nan_to_num(felt, nan=1.0) + 0.1))
    if ridge_gap:
        if prediction.ridge_gap is None:
            raise ValueError("this calibration reads the ridge baseline's gap: imagine with the checkpoint's ridge")
        features.append(np.log(prediction.ridge_gap + RIDGE_FLOOR))
    if picture:
        if prediction.picture is None:
            raise ValueError("this calibration reads the decoded frame: imagine the prediction's pictures first")
        features.extend(np.log(prediction.picture + PICTURE_FLOOR).T)
    if prediction.spread is not None:
        features.append(np.log(prediction.spread.mean(axis=1) + 1e-12))
    return features


def fit_calibrated(held_out: Prediction, iou: np.ndarray) -> dict[str, Any]:
    """The calibrated confidence's map, {"weights": [...], "spread": s, "frames": n, "ridge_gap": true,
    "picture": true}: least squares of log(1 - IoU + MARGIN) on the features of held-out frames whose true IoU
    is known (their pictures drawn: `Prediction.with_picture`)."""
    y = np.log(1.0 - iou + CalibratedTrust.MARGIN)
    design = np.column_stack([*calibration_features(held_out, True, True), np.ones(len(y))])
    weights = np.linalg.lstsq(design, y, rcond=None)[0]
    return {"weights": weights.tolist(), "spread": float(np.std(y - design @ weights)), "frames": int(len(y)),
            "ridge_gap": True, "picture": True}
