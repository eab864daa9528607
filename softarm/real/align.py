"""Time alignment of a robot's log: a uniform frame grid over the time the camera and the sensors share, the
sensors interpolated onto it from their own stamps, a constant lag between the two clocks found by
cross-correlation, and the camera's dropped frames kept as gaps."""

from dataclasses import dataclass

import numpy as np

COMPONENTS = 6  # principal components of the masks that the sensors are correlated with


def camera_period(stamps: np.ndarray) -> float:
    """The camera's frame period (s): the mean of its intervals, leaving out those of dropped frames (over 1.5
    times the median), so a rate whose stamps jitter between two intervals comes out right."""
    steps = np.diff(stamps)
    steps = steps[steps > 0]
    if not len(steps):
        return float("nan")
    return float(steps[steps < 1.5 * np.median(steps)].mean())


def rate(stamps: np.ndarray) -> float:
    """Messages per second over the span of the stamps (NaN for fewer than two)."""
    return (len(stamps) - 1) / float(stamps[-1] - stamps[0]) if len(stamps) > 1 and stamps[-1] > stamps[0] else float("nan")


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


def mask_features(masks: np.ndarray) -> np.ndarray:
    """(N, COMPONENTS) principal components of the masks (N, H, W): the body's shape in a few numbers."""
    flat = masks[:, ::2, ::2].reshape(len(masks), -1).astype(np.float32)
    flat -= flat.mean(axis=0)
    u, s, _ = np.linalg.svd(flat, full_matrices=False)
    return u[:, :COMPONENTS] * s[:COMPONENTS]


def estimate_lag(camera_times: np.ndarray, features: np.ndarray, stamps: np.ndarray, values: np.ndarray,
                 most: float, step: float) -> tuple[float, float]:
    """The lag L (s) that best explains the mask features at camera time t by the sensors stamped t + L, and
    the share of the features' variance explained there (R^2). A coarse search every `step` over [-most, most]
    is refined around its best by a finer one."""
    def score(lag: float) -> float:
        t = camera_times + lag
        ok = (t >= stamps[0]) & (t <= stamps[-1])
        if ok.sum() < 10:
            return -np.inf
        x = interpolate(t[ok], stamps, values)
        x = (x - x.mean(axis=0)) / np.maximum(x.std(axis=0), 1e-12)
        design = np.concatenate([np.ones((len(x), 1)), x, x ** 2], axis=1)
        y = features[ok] - features[ok].mean(axis=0)
        residual = y - design @ np.linalg.lstsq(design, y, rcond=None)[0]
        return 1.0 - float((residual ** 2).sum() / max((y ** 2).sum(), 1e-12))

    coarse = np.arange(-most, most + step / 2, step)
    scores = np.array([score(lag) for lag in coarse])
    best = coarse[int(np.argmax(scores))]
    fine = np.linspace(best - step, best + step, 41)
    scores = np.array([score(lag) for lag in fine])
    return float(fine[int(np.argmax(scores))]), float(scores.max())
