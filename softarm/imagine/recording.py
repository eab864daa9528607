"""Writes a replay's imagination as MCAP: any MCAP reader shows it beside the source recording.

`/imagination/image`: foxglove.RawImage, mono8, pixel probability x 255; `/imagination/iou`: JSON
(jsonschema) with the frame's IoU against the camera; `/imagination/confidence`: JSON with the model's
own trust in the frame, which a robot would have without a camera; `/imagination/surprise` and `/imagination/alarm`:
JSON with what the frame's sample felt beyond the command's prediction, and whether it raised the alarm. Log times
equal the source frames' times, so both files line up on one timeline; metadata `softarm.imagination` names the
checkpoint and the source recording (with their SHA-256 fingerprints).
"""

from pathlib import Path
from typing import TYPE_CHECKING, Union

import numpy as np
import orjson

from softarm.files import fingerprint
from softarm.record.format import json_schema
from softarm.record.mcap_file import McapFile

if TYPE_CHECKING:
    from softarm.imagine.replay_data import Replay

IMAGE = "/imagination/image"
IOU = "/imagination/iou"
CONFIDENCE = "/imagination/confidence"
SURPRISE = "/imagination/surprise"
ALARM = "/imagination/alarm"
FORMAT = "softarm-imagination/1"
META = "softarm.imagination"
IOU_SCHEMA = ("softarm.ImaginationIoU", json_schema(
    "softarm.ImaginationIoU", "Intersection over union of the imagined frame (thresholded at 0.5) and the camera frame",
    {"iou": {"type": "number", "minimum": 0, "maximum": 1}, "blind": {"type": "boolean",
                                                                       "description": "camera blacked out"}}))
CONFIDENCE_SCHEMA = ("softarm.ImaginationConfidence", json_schema(
    "softarm.ImaginationConfidence", "How far the model trusts its imagined frame, in (0, 1], as the checkpoint's "
    "train.confidence measures it (calibrated: the IoU it expects; error_head: 1 / (1 + its own estimate of the mean "
    "squared error of the normalised latent); ensemble: 1 / (1 + its members' variance))",
    {"confidence": {"type": "number", "exclusiveMinimum": 0, "maximum": 1}}))

SURPRISE_SCHEMA = ("softarm.ImaginationSurprise", json_schema(
    "softarm.ImaginationSurprise", "What the stretch felt beyond what the forward model expected from the arm's state "
    "and command: the squared residual in units of its spread on undisturbed motion, averaged over the sensors and "
    "smoothed (about 1 undisturbed); null until it speaks, at the 75th sample",
    {"surprise": {"type": ["number", "null"], "minimum": 0}}))
ALARM_SCHEMA = ("softarm.ImaginationAlarm", json_schema(
    "softarm.ImaginationAlarm", "The surprise is above the alarm threshold set on undisturbed training motion",
    {"alarm": {"type": "boolean"}}))


def write_imagination(result: "Replay", path: Union[str, Path], imagined_bytes: np.ndarray) -> Path:
    """One message per imagined frame on each topic (`imagined_bytes`: the frames as grey bytes);
    nothing is left behind if writing fails."""
    felt = bool(np.isfinite(result.surprise).any())  # a checkpoint with a forward model
    mcap = McapFile(Path(path), (IMAGE,), {IOU: IOU_SCHEMA, CONFIDENCE: CONFIDENCE_SCHEMA,
                                           **({SURPRISE: SURPRISE_SCHEMA, ALARM: ALARM_SCHEMA} if felt else {})})
    try:
        frames = np.flatnonzero(result.predicted)
        stamps = [int(round(result.times[k] * 1e9)) for k in frames]
        mcap.add_frames(stamps, {
            IMAGE: mcap.images(imagined_bytes[frames], stamps),
            IOU: [orjson.dumps({"t": ns / 1e9, "iou": float(result.iou[k]), "blind": bool(result.blind[k])})
                  for ns, k in zip(stamps, frames)],
            CONFIDENCE: [orjson.dumps({"t": ns / 1e9, "confidence": float(result.confidence[k])})
                         for ns, k in zip(stamps, frames)],
            **(surprise_messages(result, stamps, frames) if felt else {})})
        source = result.recording.path
        return mcap.close({META: {
            "format": FORMAT, "checkpoint": str(result.checkpoint), "checkpoint_sha256": fingerprint(result.checkpoint),
            "source_recording": str(source), "source_sha256": fingerprint(source),
            "metrics": orjson.dumps(result.metrics).decode()}})
    except BaseException:
        mcap.discard()
        raise


def surprise_messages(result: "Replay", stamps: list[int], frames: np.ndarray) -> dict[str, list[bytes]]:
    """One surprise and one alarm message per imagined frame."""
    value = [float(result.surprise[k]) if np.isfinite(result.surprise[k]) else None for k in frames]
    return {SURPRISE: [orjson.dumps({"t": ns / 1e9, "surprise": v}) for ns, v in zip(stamps, value)],
            ALARM: [orjson.dumps({"t": ns / 1e9, "alarm": bool(result.alarm[k])}) for ns, k in zip(stamps, frames)]}
