"""The surprise's alarm: where it starts, and the threshold that keeps false alarms within a rate."""

from typing import Sequence

import numpy as np


def alarm_onsets(surprise: np.ndarray, threshold: float) -> np.ndarray:
    """Indices where the alarm starts: the surprise rises above the threshold."""
    above = np.nan_to_num(surprise, nan=0.0) > threshold
    return np.flatnonzero(above & ~np.concatenate([[False], above[:-1]]))


def alarm_threshold(series: Sequence[tuple[np.ndarray, np.ndarray]], frame_dt: float, per_minute: float) -> float:
    """The lowest threshold at which undisturbed motion (the surprise (T,) where `calm` (T,) holds, split into
    its calm stretches) starts at most `per_minute` alarms a minute."""
    stretches = [s[a:b] for s, calm in series for a, b in runs(calm)]
    minutes = sum(len(s) for s in stretches) * frame_dt / 60.0
    values = np.concatenate([s[np.isfinite(s)] for s in stretches])
    for threshold in np.quantile(values, np.linspace(0.9, 1.0, 401)):
        if sum(len(alarm_onsets(s, threshold)) for s in stretches) <= per_minute * minutes:
            return float(threshold)
    return float(values.max())


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) of every run of True in a bool mask."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))
