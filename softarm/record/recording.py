"""A recording as arrays: what every reader of a softarm recording gets, simulated or imported from a robot's log."""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

import numpy as np

from softarm.errors import RecordingError
from softarm.record.format import IMPORTED


class TruncatedRecordingWarning(UserWarning):
    """A recording was cut short; the frames of its complete chunks were recovered."""


@dataclass(frozen=True)
class Recording:
    path: Path
    model: dict[str, Any]        # the `softarm` metadata's model document (docs/recording.md, Metadata)
    times: np.ndarray            # (T,) s
    frames: np.ndarray           # (T, H, W) uint8, 1 = arm; 0 where the camera has a gap (see `seen`)
    stretch: np.ndarray          # (T, P) m
    displacement: Optional[np.ndarray]  # (T,) m; None for an imported recording without a drive
    positions: Optional[np.ndarray]  # (T, N, 2) m, None when read with nodes=False or when it has no nodes
    complete: bool               # the run ended normally (not interrupted, not truncated)
    truncated: bool              # the file was cut short and recovered
    active: np.ndarray           # (T, D) bool: disturbance d of the model's list acts at frame k (D = 0 before /3)
    seen: np.ndarray = field(default_factory=lambda: np.ones(0, bool))  # (T,) bool: the camera has frame k
    activation: Optional[np.ndarray] = None  # (T, G) the muscles' activations of a commanded arm; None without muscles
    # (T, D) bool: the arm touches obstacle d at frame k (the label of contact; False for every other kind); None
    # where the file has obstacles but was written before `touching` was defined (unknown)
    touching: Optional[np.ndarray] = None
    sensed: dict[str, np.ndarray] = field(default_factory=dict)  # (T, S) the other sensor kinds' readings, by kind

    def __post_init__(self) -> None:
        if len(self.seen) != len(self.times):  # a simulated recording sees every frame
            object.__setattr__(self, "seen", np.ones(len(self.times), bool))

    @property
    def imported(self) -> bool:
        """Imported from a robot's log: no node positions, no known camera map (docs/recording.md)."""
        return self.model.get("kind") == IMPORTED

    @property
    def frame_dt(self) -> float:
        return float(self.model["frame_dt"])

    @property
    def world_to_pixel(self) -> np.ndarray:
        """The camera's 2x3 map M: [u, v] = M [x, y, 1]; NaN where the camera's map is not known (imported)."""
        known = self.model["camera"].get("world_to_pixel")
        return np.full((2, 3), np.nan) if known is None else np.array(known, np.float64)

    @property
    def pixels_per_metre(self) -> float:
        """From the camera's map, or an imported recording's scale; NaN where neither is known: tip errors in mm are
        then NaN, and summaries leave them out."""
        scale = self.model["camera"].get("pixels_per_metre")
        return float(np.hypot(*self.world_to_pixel[:, 0])) if scale is None else float(scale)

    def drive(self) -> np.ndarray:
        """(T,) the motor command, or a one-line refusal where the recording has none."""
        if self.displacement is None:
            raise RecordingError(f"{self.path} has no drive signal (it was imported without --drive): "
                                 "train without the drive input (train.inputs = [\"stretch\"])")
        return self.displacement


def needs_nodes_error(recording: Recording, what: str) -> RecordingError:
    """The one line for anything that needs node positions a recording does not have."""
    why = ("it was imported from a robot's log, which has no node positions" if recording.imported
           else "it was read without node positions")
    return RecordingError(f"{what} needs the arm's node positions, but {recording.path} has none: {why}")
