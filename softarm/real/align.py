"""Time alignment of a robot's log: a uniform frame grid over the time the camera and the sensors share, the
sensors interpolated onto it from their own stamps, a constant lag between the two clocks found by
cross-correlation, and the camera's dropped frames kept as gaps."""

from dataclasses import dataclass
from typing import Optional

import numpy as np

RIDGE = 0.1   # the lag search's ridge penalty, relative to the mean diagonal of the masks' Gram matrix
MOST_FRAMES = 4000  # camera frames the lag search reads at most, evenly spread: its memory stays bounded
RIVAL = 0.05  # a second peak within this share of the best fit is reported as a rival lag


def camera_period(stamps: np.ndarray) -> float:
    """The camera's frame period (s): the mean of its intervals, leaving out those of dropped frames (over 1.5
    times the median), so a rate whose stamps jitter between two intervals comes out right."""
    steps = np.diff(stamps)
    steps = steps[steps > 0]
    if not len(steps):
        return float("nan")
    return float(steps[steps < 1.5 * np.median(steps)].mean())


def dropped_frames(stamps: np.ndarray) -> int:
    """Camera frames missing from the stream: an interval of n periods lost n - 1 frames."""
    period = camera_period(stamps)
    return int(np.maximum(np.round(np.diff(stamps) / period) - 1, 0).sum()) if np.isfinite(period) else 0


def rate(stamps: np.ndarray) -> float:
    """Messages per second over the span of the stamps (NaN for fewer than two)."""
    return ((len(stamps) - 1) / float(stamps[-1] - stamps[0]) if len(stamps) > 1 and stamps[-1] > stamps[0]
            else float("nan"))


@dataclass(frozen=True)
class Grid:
    times: np.ndarray    # (T,) s, on the camera's clock
    camera: np.ndarray   # (T,) index of the camera frame of each grid frame, -1 for a gap

    @property
    def gaps(self) -> np.ndarray:
        return np.flatnonzero(self.camera < 0)


def frame_grid(camera_stamps: np.ndarray, start: float, end: float, dt: float) -> Grid:
    """Frames every dt from the first camera frame at or after `start` to `end`; each takes the camera frame
    nearest it within dt/2 (each camera frame at most once), or is a gap."""
    inside = np.flatnonzero((camera_stamps >= start - 1e-9) & (camera_stamps <= end + 1e-9))
    first = camera_stamps[inside[0]]
    times = first + dt * np.arange(int(np.floor((end - first) / dt + 1e-9)) + 1)
    nearest = np.clip(np.searchsorted(camera_stamps, times), 1, len(camera_stamps) - 1)
    nearest -= (times - camera_stamps[nearest - 1]) < (camera_stamps[nearest] - times)
    nearest = np.where(np.abs(camera_stamps[nearest] - times) <= dt / 2, nearest, -1)
    nearest[1:][(nearest[1:] == nearest[:-1]) & (nearest[1:] >= 0)] = -1
    return Grid(times, nearest)


def interpolate(times: np.ndarray, stamps: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(T, F) values (S, F) stamped `stamps` (S,), linearly interpolated at `times` (T,)."""
    return np.stack([np.interp(times, stamps, column) for column in values.T], axis=1)


@dataclass(frozen=True)
class Lag:
    lag: float                # s the sensors' stamps run ahead of the camera's
    fit: float                # held-out R^2 of the sensors predicted from the masks at that lag
    rival: Optional[float]    # another lag that fits almost as well (a nearly periodic motion), if any


def estimate_lag(camera_times: np.ndarray, masks: np.ndarray, stamps: np.ndarray, values: np.ndarray,
                 most: float, step: float) -> Lag:
    """The lag L (s) at which the masks at camera time t best predict the sensors stamped t + L.

    The readings are a function of the body's shape at the same instant, so a ridge map from the mask's pixels
    to the sensors, fitted on every other frame and scored on the rest, predicts best at the true lag: a
    cross-correlation of the two streams that needs no model of the arm. A coarse search every `step` over
    [-most, most] is refined by a finer one around its best."""
    usable = np.flatnonzero((camera_times - most >= stamps[0]) & (camera_times + most <= stamps[-1])
                            & masks.any(axis=(1, 2)))
    if len(usable) < 20:
        raise ValueError("too few frames inside the sensors' time for the search range")
    usable = usable[np.linspace(0, len(usable) - 1, min(len(usable), MOST_FRAMES)).round().astype(int)]
    pixels = masks[usable][:, ::2, ::2].reshape(len(usable), -1).astype(np.float64)
    pixels = pixels[:, pixels.std(axis=0) > 0]
    if pixels.shape[1] == 0:
        raise ValueError("the masks never change, so they cannot be matched to the sensors")
    pixels -= pixels.mean(axis=0)
    fit_on = np.arange(len(pixels)) % 2 == 0
    a, b = pixels[fit_on], pixels[~fit_on]
    gram = a.T @ a
    solve = np.linalg.solve(gram + RIDGE * np.trace(gram) / len(gram) * np.eye(len(gram)), a.T)
    times = camera_times[usable]

    def score(lag: float) -> float:
        y = interpolate(times + lag, stamps, values)
        y = (y - y.mean(axis=0)) / np.maximum(y.std(axis=0), 1e-12)
        residual = y[~fit_on] - b @ (solve @ y[fit_on])
        return 1.0 - float((residual ** 2).sum() / max((y[~fit_on] ** 2).sum(), 1e-12))

    coarse = np.arange(-most, most + step / 2, step)
    scores = np.array([score(lag) for lag in coarse])
    best = int(np.argmax(scores))
    fine = np.linspace(max(coarse[best] - step, -most), min(coarse[best] + step, most), 21)
    fine_scores = np.array([score(lag) for lag in fine])
    peaks = [i for i in range(1, len(coarse) - 1) if scores[i] >= max(scores[i - 1], scores[i + 1])
             and abs(i - best) > 2 and scores[i] >= scores[best] - RIVAL * abs(scores[best])]
    rival = float(coarse[max(peaks, key=lambda i: scores[i])]) if peaks else None
    return Lag(float(fine[int(np.argmax(fine_scores))]), float(fine_scores.max()), rival)
