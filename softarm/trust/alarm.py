"""The surprise's alarm: where it starts, and the threshold that keeps false alarms within a rate."""

from typing import Sequence

import numpy as np


def alarm_onsets(surprise: np.ndarray, threshold: float) -> np.ndarray:
    """Indices where the alarm starts: the surprise rises above the threshold."""
    above = np.nan_to_num(surprise, nan=0.0) > threshold
    return np.flatnonzero(above & ~np.concatenate([[False], above[:-1]]))


def alarm_threshold(series: Sequence[tuple[np.ndarray, np.ndarray]], frame_dt: float, per_minute: float) -> float:
    """The lowest threshold at which, and at every threshold above it, undisturbed motion (the surprise (T,) where
    `calm` (T,) holds) starts at most `per_minute` alarms a minute. An alarm is counted where it starts: one still
    on as a calm stretch begins (a push's, running on past its end) started while the world acted on the arm, and
    is no false alarm. Raising a threshold can split one alarm into two where the surprise dips between, so the
    count is not monotone in it: a threshold where it merely dips under the rate would be kept by chance."""
    allowed = per_minute * sum(int(calm.sum()) for _, calm in series) * frame_dt / 60.0
    values = np.concatenate([s[calm & np.isfinite(s)] for s, calm in series])
    grid = np.quantile(values, np.linspace(0.9, 1.0, 401))
    for i in range(len(grid) - 1, -1, -1):  # from the top (above every value: no alarm) down to the first excess
        if sum(int(calm[alarm_onsets(s, grid[i])].sum()) for s, calm in series) > allowed:
            return float(grid[i + 1])
    return float(grid[0])


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) of every run of True in a bool mask."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))
