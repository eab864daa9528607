"""Surprise: what the body felt that its own command did not predict.

The latent model's recurrent state after sample k is the arm's memory of how its body moved; with the
command of sample k + 1 (the efference copy: the robot knows what it told its motor) a linear forward model
from that state predicts the stretch it expects to feel at k + 1. The surprise is the felt stretch's
residual against that expectation, each sensor in units of its residual's spread on undisturbed motion,
squared, averaged over the sensors and smoothed over `SMOOTHING` samples: about 1 while the world leaves the
arm alone. An alarm fires while it exceeds a threshold set on undisturbed training motion for a false-alarm
rate (`train.false_alarms_per_minute`). A pure command-to-stretch simulation cannot serve: the arm swings
chaotically at its modes, so its feeling drifts from any prediction made from the command alone.

NumPy only: the streamer's surprise costs one small matrix-vector product per sample.
"""

from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np

SMOOTHING = 3.0      # samples: the exponential average's time constant (30 ms at the default rate)
RIDGE = 1e-4         # the forward model's L2 penalty, relative to its mean squared feature


@dataclass(frozen=True)
class SurpriseModel:
    weights: np.ndarray    # (H + C + 1, P): [state after sample k, command of sample k + 1, 1] -> stretch k + 1
    scale: np.ndarray      # (P,) each sensor's residual spread on undisturbed motion (normalised units)
    threshold: float       # the alarm fires while the surprise exceeds it
    felt: tuple[int, ...]     # the columns of the normalised inputs that are felt (the stretch)
    command: tuple[int, ...]  # the columns that are the command (the drive), known one sample ahead

    def residuals(self, states: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """(T,) squared normalised residual of each sample against the prediction from the sample before
        (NaN where the state before it is not known: the first sample, or NaN states)."""
        out = np.full(len(inputs), np.nan)
        if len(inputs) > 1:
            expected = self.features(states[:-1], inputs[1:]) @ self.weights
            out[1:] = (((inputs[1:, list(self.felt)] - expected) / self.scale) ** 2).mean(axis=1)
        return out

    def features(self, states: np.ndarray, next_inputs: np.ndarray) -> np.ndarray:
        return np.concatenate([states, next_inputs[:, list(self.command)], np.ones((len(states), 1))], axis=1)

    def series(self, states: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """(T,) the surprise after each sample, from the recurrent states after each (T, H) and the normalised
        inputs (T, F); NaN until the first prediction."""
        return smoothed(self.residuals(states, inputs))

    def online(self) -> "SurpriseReader":
        return SurpriseReader(self)

    def to_state(self) -> dict[str, Any]:
        return {"weights": self.weights.tolist(), "scale": self.scale.tolist(), "threshold": self.threshold,
                "felt": list(self.felt), "command": list(self.command), "smoothing": SMOOTHING}

    @classmethod
    def from_state(cls, state: dict[str, Any]) -> "SurpriseModel":
        return cls(np.asarray(state["weights"], np.float64), np.asarray(state["scale"], np.float64),
                   float(state["threshold"]), tuple(int(i) for i in state["felt"]),
                   tuple(int(i) for i in state["command"]))


def smoothed(values: np.ndarray) -> np.ndarray:
    """An exponential average with time constant SMOOTHING samples, started at the first finite value
    (NaN before it); the streamer computes the same sample by sample."""
    out = np.full(len(values), np.nan)
    level: Optional[float] = None
    for k, v in enumerate(values):
        if np.isfinite(v):
            level = v if level is None else level + (v - level) / SMOOTHING
        if level is not None:
            out[k] = level
    return out


class SurpriseReader:
    """The surprise sample by sample: keeps the prediction made from the last state and the average."""

    def __init__(self, model: SurpriseModel):
        self.model = model
        self.previous: Optional[np.ndarray] = None
        self.level: Optional[float] = None

    def step(self, state: Optional[np.ndarray], inputs: np.ndarray) -> float:
        """The surprise after this normalised sample (F,), given the state the sample leaves (H,; None before
        the model has one); NaN until the first prediction."""
        m = self.model
        if self.previous is not None:
            expected = m.features(self.previous[None], inputs[None]) @ m.weights
            value = float((((inputs[list(m.felt)] - expected[0]) / m.scale) ** 2).mean())
            self.level = value if self.level is None else self.level + (value - self.level) / SMOOTHING
        self.previous = state
        return float("nan") if self.level is None else self.level


def fit_surprise(parts: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], felt: Sequence[int],
                 command: Sequence[int], calibration: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]],
                 frame_dt: float, false_alarms_per_minute: float) -> SurpriseModel:
    """The forward model by ridge regression on `parts` (states (T, H), normalised inputs (T, F), undisturbed
    (T,) bool), the residual spread and the alarm threshold from `calibration` parts (held-out motion where
    there is some, else the same)."""
    x, y = [], []
    probe = SurpriseModel(np.zeros(0), np.ones(len(felt)), 0.0, tuple(felt), tuple(command))
    for states, inputs, calm in parts:
        keep = calm[1:] & calm[:-1] & np.isfinite(states[:-1]).all(axis=1)
        x.append(probe.features(states[:-1], inputs[1:])[keep])
        y.append(inputs[1:, list(felt)][keep])
    x, y = np.concatenate(x), np.concatenate(y)
    penalty = RIDGE * np.mean(x ** 2) * len(x) * np.eye(x.shape[1])
    penalty[-1, -1] = 0.0  # the constant is not shrunk
    weights = np.linalg.solve(x.T @ x + penalty, x.T @ y)
    unscaled = SurpriseModel(weights, np.ones(len(felt)), 0.0, tuple(felt), tuple(command))
    errors = []
    for states, inputs, calm in calibration:
        expected = unscaled.features(states[:-1], inputs[1:]) @ weights
        keep = calm[1:] & calm[:-1] & np.isfinite(expected).all(axis=1)
        errors.append((inputs[1:, list(felt)] - expected)[keep])
    scale = np.sqrt(np.mean(np.concatenate(errors) ** 2, axis=0))
    model = SurpriseModel(weights, np.maximum(scale, 1e-12), 0.0, tuple(felt), tuple(command))
    calm_series = [(model.series(s, i), c) for s, i, c in calibration]
    threshold = alarm_threshold(calm_series, frame_dt, false_alarms_per_minute)
    return SurpriseModel(weights, model.scale, threshold, tuple(felt), tuple(command))


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
