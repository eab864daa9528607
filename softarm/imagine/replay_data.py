"""Replay: what the arm imagines over a whole recording, beside what the camera saw.

`compute_replay()` computes everything a viewer or file needs (imagined frames, per-frame IoU, the
fused view of camera blackouts, metrics); `softarm.view` and `softarm.imagine.recording` only write
it out.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np

from softarm.imagine.blind import blind_mask, fused_scores
from softarm.imagine.trained import TrainedModel
from softarm.model.metrics import frame_scores, spearman, summarise
from softarm.record.reader import Recording


@dataclass(frozen=True)
class Replay:
    recording: Recording
    checkpoint: Path
    inputs: np.ndarray     # (T, F) what the imagination read: every input channel as the checkpoint reads it
    channels: list[tuple[str, int]]  # the input channels' names and widths, in the order of `inputs`
    imagined: np.ndarray   # (T, H, W) probabilities; 0 where nothing is imagined yet
    predicted: np.ndarray  # (T,) bool: frames with an imagination (all but the first history (+1) ones)
    iou: np.ndarray        # (T,) imagination IoU per frame, NaN where nothing is imagined
    confidence: np.ndarray  # (T,) the model's trust in each imagined frame, in (0, 1]; NaN where nothing is imagined
    surprise: np.ndarray   # (T,) the surprise of the sample each frame is imagined from; NaN where none is known
    alarm: np.ndarray      # (T,) bool: the surprise is above the checkpoint's alarm threshold
    blind: np.ndarray      # (T,) bool: camera blacked out
    fused: np.ndarray      # (T, H, W): the camera where it sees, the imagination where it is blind
    nodes_px: Optional[np.ndarray]  # (T, N, 2) node positions in pixel coordinates [u, v], if read
    metrics: dict[str, Any]

    @property
    def times(self) -> np.ndarray:
        return self.recording.times


def compute_replay(checkpoint: Union[str, Path], recording: Union[str, Path],
           blind: Sequence[tuple[float, float]] = (), nodes: bool = True,
                   sensor_noise: Optional[dict[str, Any]] = None, device: str = "auto") -> Replay:
    """Imagine every frame of `recording` from its input signals and score it against the camera.

    The inputs are read as the checkpoint was trained to read them, with `sensor_noise` (keys of the
    [sensing] section but pairs) replacing its imperfections. nodes=False skips the node positions
    (only the Rerun view draws them; they are a third of the reading). The networks run on `device`.
    """
    model = TrainedModel(checkpoint, device)
    reading = model.read(recording, sensor_noise, nodes)
    imaginer = model.imaginer_for(reading.config)
    rec = reading.recording
    mask = blind_mask(rec.times, blind)
    prediction, probs = imaginer.imagine(reading.inputs)
    targets = prediction.targets
    imagined = np.zeros(rec.frames.shape, np.float32)
    imagined[targets] = probs
    predicted = np.zeros(len(rec.times), bool)
    predicted[targets] = True
    scored = predicted & rec.seen  # a camera's gap has nothing to score against
    confidence, surprise = np.full(len(rec.times), np.nan), np.full(len(rec.times), np.nan)
    confidence[targets] = imaginer.confidence(prediction)
    if prediction.surprise is not None:
        surprise[targets] = prediction.surprise
    alarm = surprise > imaginer.surprise.threshold if imaginer.surprise is not None else np.zeros(len(surprise), bool)
    fused = rec.frames.astype(np.float32)
    fused[mask] = imagined[mask]
    M = rec.world_to_pixel
    imagination = frame_scores(imagined, rec.frames, rec.pixels_per_metre)
    iou = np.where(scored, imagination["iou"], np.nan)
    last = rec.times >= rec.times[-1] - 5.0 + 1e-9  # the paper's last 5 s
    metrics = {
        "recording": str(rec.path), "frames": int(len(rec.times)), "predicted_frames": int(predicted.sum()),
        "blind_frames": int(mask.sum()), "sensing": reading.config.to_dict()["sensing"],
        **{key: summarise(imagination, scored & subset) if (scored & subset).any() else None
           for key, subset in (("imagination", predicted), ("imagination_last_5s", last),
                               ("imagination_blind", mask), ("imagination_seeing", ~mask))},
        "fused": summarise(fused_scores(imagination, rec.frames, mask), rec.seen),
        "confidence": {"mean": float(confidence[targets].mean()),
                       "spearman_with_iou": spearman(confidence[scored], iou[scored])},
        "surprise": {"mean": float(np.nanmean(surprise)) if np.isfinite(surprise).any() else None,
                     "alarm_frames": int(alarm.sum()),
                     "alarms": int((alarm[1:] & ~alarm[:-1]).sum() + alarm[:1].sum())},
    }
    return Replay(recording=rec, checkpoint=model.path, inputs=reading.inputs,
                  channels=[(c.name, w) for c, w in zip(imaginer.inputs.channels, imaginer.inputs.widths)],
                  imagined=imagined, predicted=predicted, iou=iou, confidence=confidence, surprise=surprise,
                  alarm=alarm, blind=mask, fused=fused,
                  metrics=metrics,
                  nodes_px=rec.positions @ M[:, :2].T + M[:, 2] if nodes and rec.positions is not None else None)
