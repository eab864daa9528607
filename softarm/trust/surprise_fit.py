"""The surprise's forward model, its expected spread and the memory check, fitted once the latent model is trained
(docs/model.md, Surprise), from parts of normalised inputs (and the latent model's states) with their undisturbed
samples marked (`softarm.learn.trust_fits` gathers them from the training).

The fitting parts fit the forward model, the spread it expects from the arm's vigour and the memory check; the
held-out motion sets each sensor's residual spreads and the alarm's threshold. Samples near a disturbance are
left out of all of them: the model learns what undisturbed motion feels like.
"""

from dataclasses import replace
from typing import Optional, Sequence

import numpy as np

from softarm.trust.alarm import alarm_threshold
from softarm.trust.memory_check import MemoryCheck
from softarm.trust.surprise import LAGS, VIGOURS, WINDOWS, SurpriseModel, vigour

RIDGE = 1e-8          # the forward model's L2 penalty, relative to its mean squared feature
MEMORY_RIDGE = 1e-4   # the memory check's, the same way
SPREAD_RIDGE = 1e-6   # the spread map's L2 penalty per sample
SPREAD_FLOOR = 1e-3   # added to a squared residual before its logarithm

Part = tuple[np.ndarray, np.ndarray]  # normalised inputs (T, F), undisturbed (T,) bool


def fit_surprise(parts: Sequence[Part], felt: Sequence[int], command: Sequence[int], calibration: Sequence[Part],
                 frame_dt: float, false_alarms_per_minute: float) -> SurpriseModel:
    """The forward model by ridge regression on `parts`, each sensor's residual spread on `calibration` (held-out
    motion where there is some, else the same), the spread map on `parts` again, and the alarm's threshold on
    `calibration`."""
    felt, command = tuple(felt), tuple(command)
    blank = np.zeros(VIGOURS * len(WINDOWS) + 1)
    probe = SurpriseModel(np.zeros(0), np.ones(len(felt)), blank, 0.0, felt, command)
    weights = _ridge([(probe.features(x), x[LAGS:, list(felt)], _quiet(c)) for x, c in parts], RIDGE, unshrunk=-1)
    unscaled = SurpriseModel(weights, np.ones(len(felt)), blank, 0.0, felt, command)
    errors = np.concatenate([unscaled.residuals(x)[_quiet(c, pad=True)] for x, c in calibration])
    scale = np.maximum(np.sqrt(np.mean(errors ** 2, axis=0)), 1e-12)
    scaled = SurpriseModel(weights, scale, blank, 0.0, felt, command)
    spread = _ridge([(vigour(x, felt, command)[LAGS - 1:-1],
                      np.log((scaled.residuals(x)[LAGS:] ** 2).mean(axis=1) + SPREAD_FLOOR)[:, None],
                      _quiet(c) & (np.arange(LAGS, len(x)) >= max(WINDOWS))) for x, c in parts], SPREAD_RIDGE)[:, 0]
    spread[-1] += np.log(np.nanmean(np.concatenate([_ratio(replace(scaled, spread=spread), x, c) for x, c in parts])))
    model = SurpriseModel(weights, scale, spread, 0.0, felt, command)
    threshold = alarm_threshold([(model.series(x)[0], c) for x, c in calibration], frame_dt, false_alarms_per_minute)
    return SurpriseModel(weights, scale, spread, threshold, felt, command)


def fit_memory_check(parts: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], felt: Sequence[int],
                     command: Sequence[int], calibration: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]]
                     ) -> MemoryCheck:
    """Ridge regression on `parts` (states (T, H), normalised inputs (T, F), undisturbed (T,) bool), each sensor's
    spread on `calibration` parts; samples next to a disturbance or without a state are left out."""
    probe = MemoryCheck(np.zeros(0), np.ones(len(felt)), tuple(felt), tuple(command))
    weights = _ridge([(probe.features(s[:-1], x[1:]), x[1:, list(felt)], c[1:] & c[:-1]) for s, x, c in parts],
                     MEMORY_RIDGE, unshrunk=-1)
    errors = []
    for states, inputs, calm in calibration:
        expected = probe.features(states[:-1], inputs[1:]) @ weights
        keep = calm[1:] & calm[:-1] & np.isfinite(expected).all(axis=1)
        errors.append((inputs[1:, list(felt)] - expected)[keep])
    scale = np.maximum(np.sqrt(np.mean(np.concatenate(errors) ** 2, axis=0)), 1e-12)
    return MemoryCheck(weights, scale, tuple(felt), tuple(command))


def _ratio(model: SurpriseModel, inputs: np.ndarray, calm: np.ndarray) -> np.ndarray:
    """Each quiet sample's mean squared residual over what the model expected: the log-linear fit estimates the
    expected logarithm, so its constant is moved until these average 1 (the surprise's scale)."""
    return ((model.residuals(inputs) ** 2).mean(axis=1) / model.expected(inputs))[_quiet(calm, pad=True)]


def _quiet(calm: np.ndarray, pad: bool = False) -> np.ndarray:
    """For each sample from LAGS on (or every sample, `pad`: False before LAGS): it and the LAGS before it are
    undisturbed."""
    disturbed = np.convolve(~calm, np.ones(LAGS + 1), "full")[:len(calm)] > 0
    quiet = ~disturbed
    quiet[:LAGS] = False
    return quiet if pad else quiet[LAGS:]


def _ridge(parts: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], penalty: float,
           unshrunk: Optional[int] = None) -> np.ndarray:
    """Ridge regression of y on x over the kept finite rows of every (x, y, keep) part, summed part by part so the
    rows never sit in memory together. With `unshrunk`, the penalty is relative to the mean squared feature and
    that column (the constant) is not shrunk; without, it is per row and shrinks every column."""
    xtx, xty, rows, squares = 0.0, 0.0, 0, 0.0
    for x, y, keep in parts:
        keep = keep & np.isfinite(x).all(axis=1) & np.isfinite(y).all(axis=1)
        x, y = x[keep], y[keep]
        xtx, xty, rows, squares = xtx + x.T @ x, xty + x.T @ y, rows + len(x), squares + float((x ** 2).sum())
    width = np.shape(xtx)[0]
    scale = penalty * (squares / (rows * width) if unshrunk is not None else 1.0) * rows
    shrink = scale * np.eye(width)
    if unshrunk is not None:
        shrink[unshrunk, unshrunk] = 0.0
    return np.linalg.solve(xtx + shrink, xty)
