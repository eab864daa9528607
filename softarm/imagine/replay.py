"""Replay: what the arm imagines over a whole recording, beside what the camera saw.

`compute_replay()` computes everything a viewer or file needs (imagined frames, per-frame IoU, the
fused view of camera blackouts, metrics); `softarm.view` and `softarm.imagine.recording` only write
it out.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np

from softarm.learn.checkpoint import checkpoint_config, load_checkpoint
from softarm.imagine.blind import blind_mask, fused_scores
from softarm.learn.imaginer import Imaginer
from softarm.learn.fits import check_recording_fits_checkpoint
from softarm.learn.metrics import frame_scores, spearman, summarise
from softarm.record.reader import Recording, read_model, read_recording
from softarm.sense.reading import needs_nodes, sensed_stretch


@dataclass(frozen=True)
class Replay:
    recording: Recording
    checkpoint: Path
    stretch: np.ndarray    # (T, P) what the imagination read: the sensors as the checkpoint reads them
    imagined: np.ndarray   # (T, H, W) probabilities; 0 where nothing is imagined yet
    predicted: np.ndarray  # (T,) bool: frames with an imagination (all but the first history (+1) ones)
    iou: np.ndarray        # (T,) imagination IoU per frame, NaN where nothing is imagined
    confidence: np.ndarray  # (T,) the model's trust in each imagined frame, in (0, 1]; NaN where nothing is imagined
    blind: np.ndarray      # (T,) bool: camera blacked out
    fused: np.ndarray      # (T, H, W): the camera where it sees, the imagination where it is blind
    nodes_px: Optional[np.ndarray]  # (T, N, 2) node positions in pixel coordinates [u, v], if read
    metrics: dict[str, Any]

    @property
    def times(self) -> np.ndarray:
        return self.recording.times


def read_as_trained(state: dict[str, Any], checkpoint: Path, recording: Path,
                    sensor_noise: Optional[dict[str, Any]], nodes: bool = False) -> tuple[Recording, np.ndarray, dict]:
    """A recording and the signals the checkpoint reads from it: its sensors as it was trained to read them,
    with `sensor_noise` replacing the imperfections; (recording, stretch (T, P), the [sensing] used).

    A recording whose camera or sensors do not fit the checkpoint is refused before its frames are read.
    """
    config = checkpoint_config(state).replace(**{f"sensing.{k}": v for k, v in (sensor_noise or {}).items()})
    sensing = config.sensing
    check_recording_fits_checkpoint(state, read_model(recording), str(recording), str(checkpoint), sensing)
    rec = read_recording(recording, nodes=nodes or needs_nodes(sensing))
    return rec, sensed_stretch(rec, sensing), config.to_dict()["sensing"]


def compute_replay(checkpoint: Union[str, Path], recording: Union[str, Path],
           blind: Sequence[tuple[float, float]] = (), nodes: bool = True,
                   sensor_noise: Optional[dict[str, Any]] = None) -> Replay:
    """Imagine every frame of `recording` from its stretch signals and score it against the camera.

    The sensors are read as the checkpoint was trained to read them, with `sensor_noise` (keys of the
    [sensing] section but pairs) replacing its imperfections. nodes=False skips the node positions
    (only the Rerun view draws them; they are a third of the reading).
    """
    checkpoint = Path(checkpoint)
    state = load_checkpoint(checkpoint)
    rec, stretch, sensing = read_as_trained(state, checkpoint, Path(recording), sensor_noise, nodes)
    mask = blind_mask(rec.times, blind)
    imaginer = Imaginer.from_checkpoint(state)
    prediction, probs = imaginer.imagine(stretch)
    targets = prediction.targets
    imagined = np.zeros(rec.frames.shape, np.float32)
    imagined[targets] = probs
    predicted = np.zeros(len(rec.times), bool)
    predicted[targets] = True
    confidence = np.full(len(rec.times), np.nan)
    confidence[targets] = prediction.confidence
    fused = rec.frames.astype(np.float32)
    fused[mask] = imagined[mask]
    M = rec.world_to_pixel
    imagination = frame_scores(imagined, rec.frames, rec.pixels_per_metre)
    iou = np.where(predicted, imagination["iou"], np.nan)
    last = rec.times >= rec.times[-1] - 5.0 + 1e-9  # the paper's last 5 s
    metrics = {
        "recording": str(rec.path), "frames": int(len(rec.times)), "predicted_frames": int(predicted.sum()),
        "blind_frames": int(mask.sum()), "sensing": sensing,
        **{key: summarise(imagination, predicted & subset) if (predicted & subset).any() else None
           for key, subset in (("imagination", predicted), ("imagination_last_5s", last),
                               ("imagination_blind", mask), ("imagination_seeing", ~mask))},
        "fused": summarise(fused_scores(imagination, rec.frames, mask)),
        "confidence": {"mean": float(prediction.confidence.mean()),
                       "spearman_with_iou": spearman(prediction.confidence, iou[targets])},
    }
    return Replay(recording=rec, checkpoint=checkpoint, stretch=stretch, imagined=imagined, predicted=predicted, iou=iou,
                  confidence=confidence,
                  blind=mask, fused=fused, metrics=metrics,
                  nodes_px=rec.positions @ M[:, :2].T + M[:, 2] if nodes else None)
