"""The surprise's forward model, its expected spread and the memory check, fitted once the latent model is trained
(docs/model.md, Surprise), from pieces of normalised inputs with their undisturbed samples marked and their motion
group named (`softarm.learn.trust_fits` gathers them from the training).

A surprise that only knew the motions it was fitted on would cry wolf on the first new one. So everything after
the forward model is fitted out of fold: each fold (a motion group of the corpus) is judged by a forward model
fitted on the other folds' training samples (the folds dealt into `BLOCKS` blocks, for each correction's fit costs
about a minute on the corpus), and its residuals, set against its vigour and its novelty under that model, fit
each sensor's spread, the spread map, what the last errors foresee of the next (`softarm.trust.innovation`) and
the alarm's threshold. The forward model the checkpoint keeps is fitted on every fold. Samples near a disturbance
are left out of all of it: the model learns what undisturbed motion feels like.
"""

from dataclasses import replace
from typing import Iterable, NamedTuple, Optional, Sequence

import numpy as np

from softarm.trust.alarm import alarm_threshold
from softarm.trust.correction import fit_correction
from softarm.trust.innovation import ECHOES, Innovation, echoes
from softarm.trust.memory_check import MemoryCheck
from softarm.trust.surprise import DESIGN, LAGS, WINDOWS, SurpriseModel, feature_width, linear_width, told

RIDGE = 1e-8          # the forward model's L2 penalty, relative to its mean squared feature
PRECISION_RIDGE = 1e-6  # added to the linear features' second moment before it is inverted, relative to its trace
MEMORY_RIDGE = 1e-4   # the memory check's, the same way
SPREAD_RIDGE = 1e-6   # the spread map's L2 penalty per sample
SPREAD_FLOOR = 1e-3   # added to a squared residual before its logarithm
ECHO_RIDGE = 1e-6     # the innovation's L2 penalty per sample
BLOCKS = 5            # blocks the folds are dealt into for judging out of fold (a correction fitted per block)


class Piece(NamedTuple):
    """A stretch of one recording for the surprise's fit."""
    inputs: np.ndarray    # (T, F) normalised
    calm: np.ndarray      # (T,) bool: nothing acts on the arm
    fitting: np.ndarray   # (T,) bool: samples the forward model may be fitted to (the training segment)
    fold: str             # its motion group: judged by the forward model fitted without it


def fit_surprise(pieces: Sequence[Piece], felt: Sequence[int], command: Sequence[int], frame_dt: float,
                 false_alarms_per_minute: float, device: Optional[str] = None) -> Optional[SurpriseModel]:
    """The forward model by ridge regression on every fold's fitting samples, its correction fitted (on `device`)
    to what the ridge leaves; each sensor's spread, the spread map and the alarm's threshold from every piece
    judged out of fold, the folds dealt into at most `BLOCKS` blocks, each judged by a forward model fitted
    without it. None where fewer than two folds hold undisturbed samples to fit: nothing could be judged out of
    fold."""
    felt, command = tuple(felt), tuple(command)
    channels = pieces[0].inputs.shape[1]
    linear = linear_width(channels, len(command))
    probe = _model(np.zeros((feature_width(channels, len(command)), len(felt))), np.eye(linear + 1), felt, command)
    folds = {fold: _Sums() for fold in sorted({p.fold for p in pieces})}
    for piece in pieces:
        keep = _quiet(piece.calm) & piece.fitting[LAGS:]
        folds[piece.fold].add(probe.features(piece.inputs), piece.inputs[LAGS:, list(felt)], keep)
    names = [fold for fold, sums in folds.items() if sums.rows > 0]
    if len(names) < 2:
        return None
    blocks = [names[i::BLOCKS] for i in range(min(BLOCKS, len(names)))]
    blocks[0] += [fold for fold in folds if fold not in names]  # folds with nothing to fit are judged all the same
    judged = []  # per piece: unscaled residuals (T, P), the spread map's inputs (T, DESIGN), quiet (T,), calm (T,)
    for block in blocks:
        model = _forward([folds[f] for f in names if f not in block], linear, felt, command, device)
        for piece in (p for p in pieces if p.fold in block):
            features = model.features(piece.inputs)
            judged.append((model.residuals(piece.inputs, features), model.design(piece.inputs, features),
                           _quiet(piece.calm, pad=True), piece.calm))
    residuals, designs, quiet, calm = (list(part) for part in zip(*judged))
    scale = _spreads(residuals, quiet)
    errors = [e / scale for e in residuals]
    spread = _spread_map(designs, [(e ** 2).mean(axis=1) for e in errors], quiet)
    innovation = fit_innovation([e / np.sqrt(np.exp(d @ spread))[:, None] for e, d in zip(errors, designs)],
                                designs, quiet)
    judge = replace(probe, spread=spread, innovation=innovation)
    series = [(told(judge.values(e, d, np.zeros_like(e))[0]), c) for e, d, c in zip(errors, designs, calm)]
    threshold = alarm_threshold(series, frame_dt, false_alarms_per_minute)
    full = _forward([folds[f] for f in names], linear, felt, command, device)
    return replace(full, scale=scale, spread=spread, innovation=innovation, threshold=threshold)


def fit_innovation(errors: Sequence[np.ndarray], designs: Sequence[np.ndarray], quiet: Sequence[np.ndarray]
                   ) -> Innovation:
    """What the last ECHOES errors foresee of the next, by least squares over the quiet samples whose echoes are
    quiet too, from out-of-fold errors (T, P) in units of their expected spread; then each sensor's spread of what
    they leave and its spread map on the same design rows."""
    calm = []
    for q in quiet:
        keep = q.copy()
        for j in range(1, ECHOES + 1):
            keep[j:] &= q[:-j]
        keep[:ECHOES] = False
        calm.append(keep)
    persistence = _ridge(((echoes(e), e, k) for e, k in zip(errors, calm)), ECHO_RIDGE)  # one piece at a time
    news = [e - echoes(e) @ persistence for e in errors]
    scale = _spreads(news, quiet)
    spread = _spread_map(designs, [((n / scale) ** 2).mean(axis=1) for n in news], quiet)
    return Innovation(persistence, scale, spread)


def _spreads(errors: Sequence[np.ndarray], quiet: Sequence[np.ndarray]) -> np.ndarray:
    """(P,) each column's root mean square over the quiet rows of every part."""
    return np.maximum(np.sqrt(np.nanmean(np.concatenate([e[q] for e, q in zip(errors, quiet)]) ** 2, axis=0)), 1e-12)


def _spread_map(designs: Sequence[np.ndarray], squared: Sequence[np.ndarray], quiet: Sequence[np.ndarray]
                ) -> np.ndarray:
    """(DESIGN,) log expected `squared` (T,) from the design rows (T, DESIGN), by ridge over the quiet samples once
    the vigour averages have settled, its constant moved so that squared over expected averages 1 when quiet."""
    settled = [q & (np.arange(len(q)) >= LAGS + max(WINDOWS)) for q in quiet]
    spread = _ridge([(d, np.log(s + SPREAD_FLOOR)[:, None], k) for d, s, k in zip(designs, squared, settled)],
                    SPREAD_RIDGE)[:, 0]
    spread[-1] += np.log(np.nanmean(np.concatenate([(s / np.exp(d @ spread))[q]
                                                    for d, s, q in zip(designs, squared, quiet)])))
    return spread


def _forward(folds: Sequence["_Sums"], linear: int, felt: tuple[int, ...], command: tuple[int, ...],
             device: Optional[str]) -> SurpriseModel:
    """The forward model of the folds' rows: the ridge, then its correction fitted to the ridge's residual."""
    weights, precision = _solve(folds, linear)
    parts = [part for fold in folds for part in fold.parts]
    x, y = np.concatenate([x for x, _ in parts]), np.concatenate([y for _, y in parts])  # one copy of the rows
    correction = fit_correction(x[:, :linear], y - x @ weights, device)
    return replace(_model(weights, precision, felt, command), correction=correction)


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


class _Sums:
    """A ridge regression's sums, added part by part (fold by fold); `kept` also holds the rows (the correction's
    fit reads them)."""

    def __init__(self, kept: bool = True) -> None:
        self.xtx, self.xty, self.rows, self.squares = 0.0, 0.0, 0, 0.0
        self.kept = kept
        self.parts: list[tuple[np.ndarray, np.ndarray]] = []

    def add(self, x: np.ndarray, y: np.ndarray, keep: np.ndarray) -> None:
        """The kept finite rows of x (n, W) and y (n, P)."""
        keep = keep & np.isfinite(x).all(axis=1) & np.isfinite(y).all(axis=1)
        x, y = x[keep], y[keep]
        self.xtx, self.xty = self.xtx + x.T @ x, self.xty + x.T @ y
        self.rows, self.squares = self.rows + len(x), self.squares + float((x ** 2).sum())
        if self.kept:
            self.parts.append((x, y))

    @classmethod
    def joined(cls, parts: Sequence["_Sums"]) -> "_Sums":
        out = cls(kept=False)
        for part in parts:
            out.xtx, out.xty = out.xtx + part.xtx, out.xty + part.xty
            out.rows, out.squares = out.rows + part.rows, out.squares + part.squares
        return out

    def solve(self, penalty: float, unshrunk: Optional[int] = None) -> np.ndarray:
        """With `unshrunk`, the penalty is relative to the mean squared feature and that column (the constant) is
        not shrunk; without, it is per row and shrinks every column."""
        width = np.shape(self.xtx)[0]
        scale = penalty * (self.squares / (self.rows * width) if unshrunk is not None else 1.0) * self.rows
        shrink = scale * np.eye(width)
        if unshrunk is not None:
            shrink[unshrunk, unshrunk] = 0.0
        return np.linalg.solve(self.xtx + shrink, self.xty)


def _solve(folds: Sequence[_Sums], linear: int) -> tuple[np.ndarray, np.ndarray]:
    """The forward model's weights (the constant unshrunk) and the precision of its `linear` first features with
    the constant (the inverse of their second moment, lightly regularised), from the folds' sums."""
    sums = _Sums.joined(folds)
    kept = np.r_[np.arange(linear), sums.xtx.shape[0] - 1]
    moment = sums.xtx[np.ix_(kept, kept)] / sums.rows
    moment += PRECISION_RIDGE * np.trace(moment) / len(kept) * np.eye(len(kept))
    return sums.solve(RIDGE, unshrunk=-1), np.linalg.inv(moment)


def _model(weights: np.ndarray, precision: np.ndarray, felt: tuple[int, ...], command: tuple[int, ...]
           ) -> SurpriseModel:
    """A forward model with unit spreads and no spread map: what judges a fold's residuals and features."""
    return SurpriseModel(weights, np.ones(len(felt)), np.zeros(DESIGN), precision, 0.0, felt, command)


def _quiet(calm: np.ndarray, pad: bool = False) -> np.ndarray:
    """For each sample from LAGS on (or every sample, `pad`: False before LAGS): it and the LAGS before it are
    undisturbed."""
    disturbed = np.convolve(~calm, np.ones(LAGS + 1), "full")[:len(calm)] > 0
    quiet = ~disturbed
    quiet[:LAGS] = False
    return quiet if pad else quiet[LAGS:]


def _ridge(parts: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]], penalty: float,
           unshrunk: Optional[int] = None) -> np.ndarray:
    """Ridge regression of y on x over the kept finite rows of every (x, y, keep) part (`_Sums.solve`)."""
    sums = _Sums(kept=False)
    for x, y, keep in parts:
        sums.add(x, y, keep)
    return sums.solve(penalty, unshrunk)
