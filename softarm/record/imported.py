"""Reading a recording imported from a robot's log (docs/recording.md, Imported recordings).

Every frame of its grid has a stretch reading (and a drive, where the log had one); the camera has gaps (frames
between its images when the grid is finer than the camera, and the frames it dropped), which `Recording.seen`
marks: training skips them and scoring ignores them. It has no node positions and no known camera map.
"""

import warnings
from pathlib import Path
from typing import Any, Optional

import numpy as np

from softarm.errors import RecordingError
from softarm.record.decode import mono8_image, signal_values
from softarm.record.format import EXCITATION, IMAGE, STRETCH
from softarm.record.recording import Recording, TruncatedRecordingWarning


def imported_recording(path: Path, model: dict[str, Any], run: Optional[dict[str, str]],
                       messages: dict[str, dict[int, bytes]], truncated: bool) -> Recording:
    """The arrays of an imported recording from its messages by topic (log time ns -> bytes)."""
    drive = messages.get(EXCITATION) or {}
    stamps = sorted(set(messages[STRETCH]) & set(drive) if drive else messages[STRETCH])  # a cut file: frames whole
    if not stamps:
        raise RecordingError(f"{path} holds no complete frame")
    height, width = model["camera"]["height"], model["camera"]["width"]
    frames = np.zeros((len(stamps), height, width), np.uint8)
    seen = np.zeros(len(stamps), bool)
    for k, stamp in enumerate(stamps):
        data = messages[IMAGE].get(stamp)
        if data is not None:
            frames[k] = mono8_image(data, path, height, width) > 127
            seen[k] = True
    if not seen.any():
        raise RecordingError(f"{path} holds no camera frame")
    stretch = signal_values(messages[STRETCH], stamps, ("stretch",), (len(model["sensors"]),), STRETCH, path)
    displacement = None
    if drive:
        displacement = signal_values(drive, stamps, ("displacement",), (), EXCITATION, path)
    if truncated:
        warnings.warn(f"{path} is truncated: recovered {len(stamps)} complete frames", TruncatedRecordingWarning,
                      stacklevel=3)
    return Recording(path=path, model=model, times=np.array(stamps, np.int64) / 1e9, frames=frames, stretch=stretch,
                     displacement=displacement, positions=None,
                     complete=run is not None and run.get("complete") == "true" and not truncated, truncated=truncated,
                     active=np.zeros((len(stamps), 0), bool), seen=seen)
