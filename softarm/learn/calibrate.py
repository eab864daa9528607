"""The calibrated confidence's map (`softarm.model.trust.CalibratedTrust`), fitted once the model is whole.

On held-out frames (the test segments, the validation recordings whole), each recording imagined from its
first sample as replay would: the frames' true IoU against what the model knows without a camera.
"""

from typing import Any

import numpy as np

from softarm.learn.evaluate import evenly, imaginer_of
from softarm.learn.train_state import TrainState
from softarm.model.metrics import iou_per_frame
from softarm.model.prediction import Prediction
from softarm.model.trust import CalibratedTrust, calibration_features

MAX_FRAMES = 20_000  # held-out frames the map is fitted on, evenly spread


def fit_calibration(state: TrainState) -> dict[str, Any]:
    """{"weights": [...], "spread": s, "frames": n, "ridge_gap": true}: least squares of log(1 - IoU + margin)
    on the features, the gap to the ridge baseline's latent among them (its baselines are fitted first)."""
    imaginer, data = imaginer_of(state), state.data
    parts, where = [], []
    for n, (seq, prediction) in enumerate(zip(data.sequences, imaginer.predict_many([s.inputs for s in data.sequences]))):
        start, end = seq.segment("test")
        keep = (prediction.targets >= start) & (prediction.targets < end)
        if seq.seen is not None:
            keep &= seq.seen[prediction.targets]
        parts.append(prediction.take(keep))
        where.append(np.stack([np.full(int(keep.sum()), n), parts[-1].targets], axis=1))
    picked = evenly(sum(len(w) for w in where), MAX_FRAMES)
    held_out, where = Prediction.join(parts).take(picked), np.concatenate(where)[picked]
    iou = iou_per_frame(imaginer.decode(held_out.latents), data.target_frames(where))
    y = np.log(1.0 - iou + CalibratedTrust.MARGIN)
    design = np.column_stack([*calibration_features(held_out, True), np.ones(len(y))])
    weights = np.linalg.lstsq(design, y, rcond=None)[0]
    return {"weights": weights.tolist(), "spread": float(np.std(y - design @ weights)), "frames": int(len(y)),
            "ridge_gap": True}
