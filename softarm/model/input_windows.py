"""Input windows: the last `history` samples before the frame they imagine.

The window for frame k is samples k - history - lead + 1 .. k - lead (lead = 1 is the paper's set-up: the
samples before frame k; 0 ends the window at frame k's own sample). Every sample lies in [start, end), so
no window straddles a split of the recording.
"""

from typing import Optional

import numpy as np


def input_windows(series: np.ndarray, history: int, lead: int, start: int = 0,
                  end: Optional[int] = None) -> tuple[np.ndarray, np.ndarray]:
    """The windows (M, history, P) of series[start:end] (T, P) and the frame index each imagines (M,)."""
    end = len(series) if end is None else end
    targets = np.arange(start + history - 1 + lead, end)
    first = targets - lead - history + 1
    windows = series[first[:, None] + np.arange(history)] if len(targets) else np.zeros((0, history, series.shape[1]))
    return windows, targets


def window_count(frames: int, history: int, lead: int) -> int:
    """How many windows `input_windows` finds in a segment of `frames` frames."""
    return max(0, frames - (history - 1 + lead))
