"""Replay: what the arm imagines over a whole recording, beside what the camera saw.

`replay()` computes everything a viewer or file needs (imagined frames, per-frame IoU, the fused
view of camera blackouts, metrics); `softarm.viz`, `softarm.imagination_recording` and
`softarm.filmstrip` only write it out.
"""

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np
from PIL import Image

from softarm.checkpoint import load_checkpoint
from softarm.errors import BlindRangeError, RecordingError
from softarm.filmstrip import filmstrip
from softarm.imagine import Imaginer
from softarm.metrics import EPS, frame_scores, summarise
from softarm.recording import Recording, read_model, read_recording


@dataclass(frozen=True)
class Replay:
    recording: Recording
    checkpoint: Path
    imagined: np.ndarray   # (T, H, W) probabilities; 0 where nothing is imagined yet
    predicted: np.ndarray  # (T,) bool: frames with an imagination (all but the first history (+1) ones)
    iou: np.ndarray        # (T,) imagination IoU per frame, NaN where nothing is imagined
    blind: np.ndarray      # (T,) bool: camera blacked out
    fused: np.ndarray      # (T, H, W): the camera where it sees, the imagination where it is blind
    nodes_px: Optional[np.ndarray]  # (T, N, 2) node positions in pixel coordinates [u, v], if read
    metrics: dict[str, Any]

    @property
    def times(self) -> np.ndarray:
        return self.recording.times

    @cached_property
    def imagined_bytes(self) -> np.ndarray:
        """The imagined frames as grayscale bytes, computed once for every writer that needs them."""
        return probability_bytes(self.imagined)


def parse_blind(ranges: Sequence[str]) -> list[tuple[float, float]]:
    """'START:END' strings in seconds -> [(start, end)]."""
    out = []
    for text in ranges:
        start, sep, end = text.partition(":")
        try:
            pair = (float(start), float(end))
        except ValueError:
            pair = None
        if not sep or pair is None or not pair[0] < pair[1]:
            raise BlindRangeError(f"--blind {text!r}: give START:END in seconds with START < END, e.g. 95:100")
        out.append(pair)
    return out


def blind_mask(times: np.ndarray, ranges: Sequence[tuple[float, float]]) -> np.ndarray:
    """Frames whose time lies in any [start, end) range; a range must overlap the recording."""
    mask = np.zeros(len(times), bool)
    end_time = times[-1] + (times[1] - times[0] if len(times) > 1 else 0.0)
    for start, end in ranges:
        if start < times[0] - 1e-9 or end > end_time + 1e-9:
            raise BlindRangeError(f"--blind {start:g}:{end:g} is outside the recording, which covers "
                                  f"{times[0]:g}..{end_time:g} s")
        mask |= (times >= start - 1e-9) & (times < end - 1e-9)
    return mask


def check_fits(state: dict[str, Any], model: dict[str, Any], recording: Path, checkpoint: Path) -> None:
    """Refuse a recording whose camera or sensors differ from those the checkpoint was trained on."""
    shape = (model["camera"]["height"], model["camera"]["width"])
    trained_shape, sensors = tuple(state["image_shape"]), state["sensor_count"]
    if shape != trained_shape:
        raise RecordingError(f"{recording} has {shape[0]}x{shape[1]} images but {checkpoint} was trained on "
                             f"{trained_shape[0]}x{trained_shape[1]}")
    if len(model["sensors"]) != sensors:
        raise RecordingError(f"{recording} has {len(model['sensors'])} stretch sensors but {checkpoint} "
                             f"was trained with {sensors}")


def replay(checkpoint: Union[str, Path], recording: Union[str, Path],
           blind: Sequence[tuple[float, float]] = (), nodes: bool = True) -> Replay:
    """Imagine every frame of `recording` from its stretch signals and score it against the camera.

    nodes=False skips the node positions (only the Rerun view draws them; they are a third of the reading).
    """
    checkpoint = Path(checkpoint)
    state = load_checkpoint(checkpoint)
    check_fits(state, read_model(recording), Path(recording), checkpoint)  # before reading every frame
    rec = read_recording(recording, nodes=nodes)
    mask = blind_mask(rec.times, blind)
    imaginer = Imaginer.from_checkpoint(state)
    targets, probs = imaginer.imagine(rec.stretch)
    imagined = np.zeros(rec.frames.shape, np.float32)
    imagined[targets] = probs
    predicted = np.zeros(len(rec.times), bool)
    predicted[targets] = True
    fused = rec.frames.astype(np.float32)
    fused[mask] = imagined[mask]
    M = np.array(rec.model["camera"]["world_to_pixel"])
    ppm = float(np.hypot(*M[:, 0]))
    imagination = frame_scores(imagined, rec.frames, ppm)
    iou = np.where(predicted, imagination["iou"], np.nan)
    last = rec.times >= rec.times[-1] - 5.0 + 1e-9  # the paper's last 5 s
    metrics = {
        "recording": str(rec.path), "frames": int(len(rec.times)), "predicted_frames": int(predicted.sum()),
        "blind_frames": int(mask.sum()),
        **{key: summarise(imagination, predicted & subset) if (predicted & subset).any() else None
           for key, subset in (("imagination", predicted), ("imagination_last_5s", last),
                               ("imagination_blind", mask), ("imagination_seeing", ~mask))},
        "fused": summarise(fused_scores(imagination, rec.frames, mask)),
    }
    return Replay(recording=rec, checkpoint=checkpoint, imagined=imagined, predicted=predicted, iou=iou,
                  blind=mask, fused=fused, metrics=metrics,
                  nodes_px=rec.positions @ M[:, :2].T + M[:, 2] if nodes else None)


CHUNK = 1024  # frames per step of the array conversions: small temporaries, few page faults


def fused_scores(imagination: dict[str, np.ndarray], frames: np.ndarray, blind: np.ndarray) -> dict[str, np.ndarray]:
    """Per-frame scores of the fused view without a second pass: the imagination's where the camera is
    blind, and where it sees, the camera's own frame scored against itself (BCE of the clipped 0/1
    pixels, IoU and Dice 1, tip error 0, NaN for an empty frame as `frame_scores` gives)."""
    empty = ~frames.any(axis=(1, 2))
    camera = {"bce": np.full(len(frames), -np.log(1 - EPS)), "iou": np.ones(len(frames)),
              "dice": np.ones(len(frames)), "tip_mm": np.where(empty, np.nan, 0.0)}
    return {key: np.where(blind, imagination[key], camera[key]) for key in camera}


def probability_bytes(frames: np.ndarray) -> np.ndarray:
    """Pixel probabilities in [0, 1] as grayscale bytes 0..255 (round to nearest)."""
    out = np.empty(frames.shape, np.uint8)
    for start in range(0, len(frames), CHUNK):
        chunk = np.clip(frames[start:start + CHUNK], 0.0, 1.0) * 255 + 0.5
        out[start:start + CHUNK] = chunk.astype(np.uint8)
    return out


DIFFERENCE_CLASSES = ("neither", "extra in the imagination", "missed by the imagination", "both")
DIFFERENCE_COLOURS = np.array([(0, 0, 0), (40, 110, 255), (230, 40, 40), (255, 255, 255)], np.uint8)


def difference_codes(truth: np.ndarray, imagined: np.ndarray) -> np.ndarray:
    """(T, H, W) uint8 class per pixel: 0 neither, 1 extra (blue), 2 missed (red), 3 both (white)."""
    out = np.empty(truth.shape, np.uint8)
    for start in range(0, len(truth), CHUNK):
        chunk = slice(start, start + CHUNK)
        out[chunk] = (truth[chunk] > 0).astype(np.uint8) * 2 + (imagined[chunk] >= 0.5)
    return out


def filmstrip_of(result: Replay, columns: int = 8) -> Image.Image:
    """Rows camera / imagined / difference at evenly spaced imagined frames (the README's picture)."""
    frames = np.flatnonzero(result.predicted)
    picks = frames[np.linspace(0, len(frames) - 1, columns).round().astype(int)]
    truth = result.recording.frames[picks]
    rows = [truth, result.imagined[picks], DIFFERENCE_COLOURS[difference_codes(truth, result.imagined[picks])] / 255.0]
    return filmstrip(rows, ["camera", "imagined", "difference"], result.times[picks])
