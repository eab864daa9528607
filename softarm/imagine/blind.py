"""Camera blackouts: which frames the camera misses, and how the fused view (camera where it sees,
imagination where it is blind) scores."""

import math
from typing import Sequence

import numpy as np

from softarm.errors import BlindRangeError
from softarm.model.metrics import EPS


def parse_blind(ranges: Sequence[str], option: str = "--blind") -> list[tuple[float, float]]:
    """'START:END' strings in seconds -> [(start, end)]; `option` names them in an error."""
    out = []
    for text in ranges:
        start, sep, end = text.partition(":")
        try:
            pair = (float(start), float(end))
        except ValueError:
            pair = None
        if not sep or pair is None or not (math.isfinite(pair[0]) and not math.isnan(pair[1]) and pair[0] < pair[1]):
            raise BlindRangeError(f"{option} {text!r}: give START:END in seconds with START < END, e.g. 95:100")
        out.append(pair)
    return out


def blind_mask(times: np.ndarray, ranges: Sequence[tuple[float, float]]) -> np.ndarray:
    """Frames whose time lies in any [start, end) range; a range must overlap the recording (the part of it
    beyond the recording is no frame)."""
    mask = np.zeros(len(times), bool)
    end_time = times[-1] + (times[1] - times[0] if len(times) > 1 else 0.0)
    for start, end in ranges:
        if end <= times[0] + 1e-9 or start >= end_time - 1e-9:
            raise BlindRangeError(f"--blind {start:g}:{end:g} lies outside the recording, which covers "
                                  f"{times[0]:g}..{end_time:g} s")
        mask |= (times >= start - 1e-9) & (times < end - 1e-9)
    return mask


def fused_scores(imagination: dict[str, np.ndarray], frames: np.ndarray, blind: np.ndarray) -> dict[str, np.ndarray]:
    """Per-frame scores of the fused view without a second pass: the imagination's where the camera is
    blind, and where it sees, the camera's own frame scored against itself (BCE of the clipped 0/1
    pixels, IoU and Dice 1, tip error 0, NaN for an empty frame as `frame_scores` gives)."""
    empty = ~frames.any(axis=(1, 2))
    camera = {"bce": np.full(len(frames), -np.log(1 - EPS)), "iou": np.ones(len(frames)),
              "dice": np.ones(len(frames)), "tip_mm": np.where(empty, np.nan, 0.0)}
    return {key: np.where(blind, imagination[key], camera[key]) for key in camera}
