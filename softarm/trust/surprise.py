"""Surprise: what the body felt that its own command did not predict, told apart from what is merely new.

The forward model is the arm's expectation of its own feeling: a map from the last `LAGS` samples of every input
channel and the command of the next sample (the efference copy: the robot knows what it told its motor) to the
stretch it expects to feel next. Linear in those, plus the products of the newest sample and its first difference
(`quadratic`): the body's mechanics are close to linear over one 10 ms step, and the sensors' geometry and a
softened spring bend them by a product, not more, so the map still extrapolates to motions the corpus never showed.
What that regression leaves, a small network on the same lagged inputs takes (`softarm.trust.correction`): over
a tenth of a second the arm's state is not linear in what the sensors felt, and on a new motion that structured
residual would hide a push.

How far a felt sample may stray depends on how the arm is moving and on how new the motion is: a prediction is
sharper while the arm hangs still than while it whips at a resonance, and sharper on motions like those it was
fitted on than on one it never saw. So each residual is divided by the spread it is expected to have, a
log-linear map (`spread`) from the arm's recent vigour (exponential averages of the squared first and second
differences of the stretch and of the command's second differences over `WINDOWS` samples, known before the
sample) and from the motion's novelty (the Mahalanobis length of the forward model's linear features under the
ones it was fitted on, `novelty`). The map, each sensor's spread and the alarm's threshold are fitted out of fold:
each motion group of the corpus is judged by a forward model fitted without it (`softarm.trust.surprise_fit`), so
they learn how much a new motion costs the prediction, and a push still stands out (the motion before it is
ordinary). On a motion new to it the forward model errs the same way for many samples in a row, and a push hides in
an error that was already there; so the residuals, in units of their expected spread, are also judged by what the
last few of them did not foresee (`softarm.trust.innovation`). The surprise is the average of two ratios, each
about 1 while the world leaves the arm alone: the mean over sensors of the squared residual in units of each
sensor's spread over that expectation, and the mean squared innovation over its own; smoothed over `SMOOTHING`
samples. The first holds a load that stays, the second marks what changed at this sample. The alarm fires while
the surprise exceeds the threshold. The surprise is silent (NaN) until sample `WARM`: its spread map and its
innovation were fitted only where the vigour averages had settled and every echo was an error made, and before
that an arm starting to move (its averages still at rest, its echoes zero) reads as a disturbance it is not.

Sensors noisier than those the model was fitted on (`heard_through`) would make every sample surprising. Their
white noise (and quantisation) is known, so its share is expected too: the residual's extra variance through the
forward model's weights (and, to first order, its products and its correction) is added to the expectation, the
products' bias is taken off the prediction, and the noise's share of the vigour averages and of the novelty is
taken off them.

NumPy only: the streamer's surprise costs a few small matrix-vector products per sample.
"""

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Optional

import numpy as np

from softarm.trust.correction import Correction
from softarm.trust.innovation import ECHOES, Innovation
from softarm.trust.memory_check import MemoryCheck

KIND = "innovation"  # the checkpoint's name for this surprise (earlier ones are refitted, not read)
LAGS = 10            # samples of every input channel the forward model reads (100 ms at the default rate)
WINDOWS = (5.0, 50.0)  # samples: time constants of the vigour averages
SMOOTHING = 3.0      # samples: the surprise's exponential average (30 ms at the default rate)
FLOOR = 1e-6         # added to the vigour averages before their logarithm (normalised units squared)
NOVELTY_FLOOR = 1e-3  # added to the squared Mahalanobis length before its logarithm
VIGOURS = 3          # signals averaged per window: stretch's 2nd and 1st differences, command's 2nd difference
DESIGN = VIGOURS * len(WINDOWS) + 2  # the spread map's inputs: the log vigours, the log novelty, 1
WARM = LAGS + ECHOES  # the first sample the surprise speaks at: every echo an error made, the averages settled


def linear_width(channels: int, commands: int) -> int:
    """Columns of the forward model's linear features: LAGS samples of every channel, the next command."""
    return LAGS * channels + commands


def quadratic_width(channels: int) -> int:
    """Columns of its products: every pair (with itself) of the newest sample's channels and their differences."""
    return 2 * channels * (2 * channels + 1) // 2


def feature_width(channels: int, commands: int) -> int:
    return linear_width(channels, commands) + quadratic_width(channels) + 1


def _pairs(channels: int) -> tuple[np.ndarray, np.ndarray]:
    return np.triu_indices(2 * channels)


@dataclass(frozen=True)
class SurpriseModel:
    weights: np.ndarray    # (feature_width, P): [inputs k, ..., k - LAGS + 1, command k + 1, products, 1] -> k + 1
    scale: np.ndarray      # (P,) each sensor's out-of-fold residual spread on undisturbed motion (normalised units)
    spread: np.ndarray     # (DESIGN,) log expected squared residual from [log vigours after k, log novelty, 1]
    precision: np.ndarray  # (linear_width + 1,)^2: inverse second moment of [linear features, 1] it was fitted on
    threshold: float       # the alarm fires while the surprise exceeds it
    felt: tuple[int, ...]     # the columns of the normalised inputs that are felt (the sensors: stretch, bend)
    command: tuple[int, ...]  # the columns that are the command, known one sample ahead
    memory: Optional[MemoryCheck] = None  # how well the latent model's state foresees the stretch (the confidence's)
    correction: Optional[Correction] = None  # a network's correction of the prediction, on the linear features
    innovation: Optional[Innovation] = None  # what the last errors foresee of the next: the surprise's second half
    noise: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (P,) or empty: `heard_through`

    def heard_through(self, variance: np.ndarray) -> "SurpriseModel":
        """This model for readings whose felt columns carry `variance` (P,) more white noise (normalised units
        squared) than those it was fitted on: a property of the sensors read, so never saved with the model."""
        return replace(self, noise=np.asarray(variance, np.float64))

    @property
    def channels(self) -> int:
        """F, the input channels, from the linear features' count (the precision's side less the constant)."""
        return (self.precision.shape[0] - 1 - len(self.command)) // LAGS

    @property
    def inflation(self) -> np.ndarray:
        """(VIGOURS,) what the extra noise adds to each vigour signal on average: the mean over sensors of its
        variance through the 2nd and the 1st difference (6 and 2 times it); none to the command's."""
        mean = float(self.noise.mean()) if self.noise.size else 0.0
        return np.array([6.0 * mean, 2.0 * mean, 0.0])

    @cached_property
    def novelty_inflation(self) -> float:
        """What the extra noise adds to the squared Mahalanobis length on average: its variance on every lagged
        felt entry through the precision's diagonal, over the linear features' count."""
        if not self.noise.size:
            return 0.0
        f = self.channels
        rows = [lag * f + c for lag in range(LAGS) for c in self.felt]
        return float(np.tile(self.noise, LAGS) @ np.diag(self.precision)[rows]) / (self.precision.shape[0] - 1)

    def features(self, inputs: np.ndarray) -> np.ndarray:
        """(T - LAGS, feature_width): what predicts each sample from LAGS on, from a normalised series (T, F)."""
        t = len(inputs)
        lagged = [inputs[LAGS - 1 - j:t - 1 - j] for j in range(LAGS)]
        z = np.concatenate([inputs[LAGS - 1:t - 1], inputs[LAGS - 1:t - 1] - inputs[LAGS - 2:t - 2]], axis=1)
        a, b = _pairs(inputs.shape[1])
        return np.concatenate([*lagged, inputs[LAGS:, list(self.command)], z[:, a] * z[:, b],
                               np.ones((t - LAGS, 1))], axis=1)

    def linear(self, features: np.ndarray) -> np.ndarray:
        """[linear features, 1] of feature rows: what the novelty measures."""
        return np.concatenate([features[:, :self.precision.shape[0] - 1], features[:, -1:]], axis=1)

    def novelty(self, features: np.ndarray) -> np.ndarray:
        """(n,) log of the squared Mahalanobis length of each row's linear features per feature (about 1 on the
        motion it was fitted on), less the extra noise's share."""
        x = self.linear(features)
        d2 = np.einsum("ij,jk,ik->i", x, self.precision, x) / x.shape[1] - self.novelty_inflation
        return np.log(np.maximum(d2, 0.0) + NOVELTY_FLOOR)

    def _inputs(self, features: np.ndarray) -> np.ndarray:
        """The linear features of feature rows without the constant: what the correction reads."""
        return features[:, :self.precision.shape[0] - 1]

    def corrected(self, features: np.ndarray) -> np.ndarray:
        """(n, P) the correction's share of each row's prediction (0 without one)."""
        if self.correction is None:
            return np.zeros((len(features), len(self.felt)))
        return self.correction(self._inputs(features))

    def predicted(self, features: np.ndarray) -> np.ndarray:
        """(n, P) the expected felt sample of each row (the ridge's and the correction's), less the products'
        bias from the extra noise."""
        out = features @ self.weights + self.corrected(features)
        if self.noise.size and self.noise.any():
            out -= self._noise_bias
        return out

    @property
    def _products(self) -> slice:
        start = self.precision.shape[0] - 1
        return slice(start, self.weights.shape[0] - 1)

    @cached_property
    def _noise_bias(self) -> np.ndarray:
        """(P,) what the extra noise adds to the products' prediction on average: their weights times its
        covariance over the newest sample and its first difference."""
        f = self.channels
        var = np.zeros(f)
        var[list(self.felt)] = self.noise
        cov = np.zeros((2 * f, 2 * f))
        cov[:f, :f] = cov[:f, f:] = cov[f:, :f] = np.diag(var)
        cov[f:, f:] = 2.0 * np.diag(var)
        return cov[_pairs(f)] @ self.weights[self._products]

    def noise_floors(self, features: np.ndarray) -> np.ndarray:
        """(n, P) the squared residual the extra noise adds to each sensor, in units of its spread, to first order:
        the felt sample's own noise, and every lagged felt input's through the prediction's gradient at that row
        (the weights, the products' for the newest two samples, the correction's)."""
        if not self.noise.size or not self.noise.any():
            return np.zeros((len(features), len(self.felt)))
        f, felt, w = self.channels, list(self.felt), self.weights
        z = np.concatenate([features[:, :f], features[:, :f] - features[:, f:2 * f]], axis=1)  # (n, 2F)
        grad = np.einsum("nj,mjp->nmp", z, self._gradient_map)  # d prediction / d z, (n, 2F, P)
        rows = [lag * f + c for lag in range(LAGS) for c in felt]
        through = np.repeat(w[None, rows], len(features), axis=0)  # (n, LAGS P, P) d prediction / d felt input
        through[:, :len(felt)] += grad[:, felt] + grad[:, [f + c for c in felt]]  # sample k: itself, its difference
        through[:, len(felt):2 * len(felt)] -= grad[:, [f + c for c in felt]]    # sample k - 1: its difference
        if self.correction is not None:
            through += self.correction.gradient(self._inputs(features), rows)
        added = self.noise + np.einsum("r,nrp->np", np.tile(self.noise, LAGS), through ** 2)
        return added / self.scale ** 2

    @cached_property
    def _gradient_map(self) -> np.ndarray:
        """(2F, 2F, P): the products' gradient is this map applied to z (d(z_a z_b) = z_b dz_a + z_a dz_b)."""
        f = self.channels
        a, b = _pairs(f)
        q = self.weights[self._products]
        out = np.zeros((2 * f, 2 * f, q.shape[1]))
        np.add.at(out, (a, b), q)
        np.add.at(out, (b, a), q)
        return out

    def residuals(self, inputs: np.ndarray, features: Optional[np.ndarray] = None) -> np.ndarray:
        """(T, P) each felt sample's residual in units of its sensor's spread; NaN for the first LAGS. `features`:
        `self.features(inputs)` where already built (here and below)."""
        out = np.full((len(inputs), len(self.felt)), np.nan)
        if len(inputs) > LAGS:
            features = self.features(inputs) if features is None else features
            out[LAGS:] = (inputs[LAGS:, list(self.felt)] - self.predicted(features)) / self.scale
        return out

    def design(self, inputs: np.ndarray, features: Optional[np.ndarray] = None) -> np.ndarray:
        """(T, DESIGN) what the spread map reads before each sample: the log vigour after the sample before it,
        the log novelty of its features, 1; NaN for the first LAGS."""
        out = np.full((len(inputs), DESIGN), np.nan)
        if len(inputs) > LAGS:
            out[LAGS:, :-2] = vigour(inputs, self.felt, self.command, self.inflation)[LAGS - 1:-1, :-1]
            out[LAGS:, -2] = self.novelty(self.features(inputs) if features is None else features)
            out[LAGS:, -1] = 1.0
        return out

    def values(self, errors: np.ndarray, design: np.ndarray, floors: np.ndarray,
               lagged: Optional[np.ndarray] = None) -> tuple[np.ndarray, np.ndarray]:
        """(T,) each sample's surprise before smoothing, from its residuals (T, P; `residuals`), its design row
        (T, DESIGN) and the extra noise's squared residual (T, P; `noise_floors`): the mean squared residual over
        its expectation, averaged with the mean squared innovation over its own (with an innovation). And (T, P)
        the residuals in units of their expected spread, the errors the innovation reads (`innovation.echoes`).
        `lagged`: those errors before each row where the rows are not a whole series (the streamer's)."""
        motion = np.exp(design @ self.spread)
        total = motion + floors.mean(axis=1)
        plain = (errors ** 2).mean(axis=1) / total
        normal = errors / np.sqrt(total)[:, None]
        if self.innovation is None:
            return plain, normal
        news = self.innovation.news(normal, lagged)
        expected = self.innovation.expected(design, motion / total, floors / total[:, None])
        return 0.5 * (plain + (news ** 2).mean(axis=1) / expected), normal

    def series(self, inputs: np.ndarray, states: Optional[np.ndarray] = None) -> tuple[np.ndarray, np.ndarray]:
        """(T,) the surprise after each sample of a normalised series (T, F); NaN before sample WARM. And
        (T,) the memory check's residual, smoothed the same way, from the latent model's states (T, H) after each
        sample (all NaN without a memory check or states)."""
        memory = (self.memory.residuals(states, inputs) if self.memory is not None and states is not None
                  else np.full(len(inputs), np.nan))
        if len(inputs) <= LAGS:
            return np.full(len(inputs), np.nan), smoothed(memory)
        features = self.features(inputs)
        floors = np.zeros((len(inputs), len(self.felt)))
        floors[LAGS:] = self.noise_floors(features)
        values, _ = self.values(self.residuals(inputs, features), self.design(inputs, features), floors)
        return told(values), smoothed(memory)

    def online(self) -> "SurpriseReader":
        return SurpriseReader(self)

    def to_state(self) -> dict[str, Any]:
        return {"kind": KIND, "lags": LAGS, "windows": list(WINDOWS), "smoothing": SMOOTHING, "echoes": ECHOES,
                "warm": WARM, "weights": self.weights, "scale": self.scale, "spread": self.spread,
                "precision": self.precision, "threshold": self.threshold, "felt": list(self.felt),
                "command": list(self.command),
                **({"memory": self.memory.to_state()} if self.memory is not None else {}),
                **({"correction": self.correction.to_state()} if self.correction is not None else {}),
                **({"innovation": self.innovation.to_state()} if self.innovation is not None else {})}

    @classmethod
    def from_state(cls, state: dict[str, Any]) -> "SurpriseModel":
        felt, command = tuple(int(i) for i in state["felt"]), tuple(int(i) for i in state["command"])
        memory = MemoryCheck.from_state(state["memory"], felt, command) if state.get("memory") else None
        correction = Correction.from_state(state["correction"]) if state.get("correction") else None
        innovation = Innovation.from_state(state["innovation"]) if state.get("innovation") else None
        return cls(np.asarray(state["weights"], np.float64), np.asarray(state["scale"], np.float64),
                   np.asarray(state["spread"], np.float64), np.asarray(state["precision"], np.float64),
                   float(state["threshold"]), felt, command, memory, correction, innovation)

    @staticmethod
    def current(state: dict[str, Any]) -> bool:
        """Whether a checkpoint's surprise state is this softarm's kind (earlier ones knew no innovation, or set
        their threshold on a surprise that spoke before it was warm)."""
        settings = [state.get(key) for key in ("kind", "lags", "windows", "smoothing", "echoes", "warm")]
        plain = all(isinstance(value, (str, int, float, list)) for value in settings)
        return plain and settings == [KIND, LAGS, list(WINDOWS), SMOOTHING, ECHOES, WARM]


FIRST = np.array([2, 1, 2])  # the first sample at which each vigour signal is defined


def vigour_signals(inputs: np.ndarray, felt: tuple[int, ...], command: tuple[int, ...]) -> np.ndarray:
    """(T, VIGOURS) the squared 2nd and 1st differences of the felt channels (mean over sensors) and the squared
    2nd difference of the command (mean over its channels; 0 without one); NaN before each is defined (FIRST)."""
    y, u = inputs[:, list(felt)], inputs[:, list(command)]
    out = np.full((len(inputs), VIGOURS), np.nan)
    if len(inputs) > 2:
        out[2:, 0] = (np.diff(y, 2, axis=0) ** 2).mean(axis=1)
        out[2:, 2] = (np.diff(u, 2, axis=0) ** 2).mean(axis=1) if u.shape[1] else 0.0
    if len(inputs) > 1:
        out[1:, 1] = (np.diff(y, 1, axis=0) ** 2).mean(axis=1)
    return out


def vigour(inputs: np.ndarray, felt: tuple[int, ...], command: tuple[int, ...],
           inflation: Optional[np.ndarray] = None) -> np.ndarray:
    """(T, VIGOURS * len(WINDOWS) + 1) the log vigour after each sample, with a constant: each signal's
    exponential average over each window, started at its first value (NaN before it), less its `inflation`
    (VIGOURS,; the share of noise the model was not fitted with) down to 0."""
    signals = vigour_signals(inputs, felt, command)
    less = np.zeros(VIGOURS) if inflation is None else inflation
    columns = [np.log(np.maximum(averaged(s, 1.0 / window, first) - c, 0.0) + FLOOR)
               for window in WINDOWS for s, first, c in zip(signals.T, FIRST, less)]
    return np.column_stack([*columns, np.ones(len(inputs))])


def averaged(signal: np.ndarray, rate: float, first: int) -> np.ndarray:
    """The exponential average level <- (1 - rate) level + rate x of `signal` (T,) from its sample `first` on
    (NaN before), computed as the streamer does, sample by sample."""
    out = [float("nan")] * min(first, len(signal))
    if len(signal) > first:
        level, keep = float(signal[first]), 1.0 - rate
        out.append(level)
        for value in signal[first + 1:].tolist():
            level = keep * level + rate * value
            out.append(level)
    return np.asarray(out)


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


def told(values: np.ndarray) -> np.ndarray:
    """The surprise as replay and the alarm see it, from its values before smoothing (T,; `SurpriseModel.values`
    over a whole series): silent before sample WARM, then smoothed."""
    heard = np.array(values, np.float64)
    heard[:WARM] = np.nan
    return smoothed(heard)


class SurpriseReader:
    """The surprise sample by sample (a robot's loop calls it every 10 ms): the last LAGS samples, from which the
    forward model's features are built as the batch builds them, the vigour averages, the last ECHOES errors, the
    latent model's last state and the two smoothed values."""

    def __init__(self, model: SurpriseModel):
        self.model = model
        self.felt, self.command = np.array(model.felt, int), np.array(model.command, int)
        self.history = np.zeros((LAGS + 1, model.channels))  # the last LAGS samples, then room for the new one
        self.row = np.ones((1, model.weights.shape[0]))  # the forward model's features, as `features` lays them out
        self.pairs = _pairs(model.channels)
        self.linear = np.r_[np.arange(model.precision.shape[0] - 1), model.weights.shape[0] - 1]
        self.novelty_shift = model.novelty_inflation
        self.design = np.ones(DESIGN)
        self.echoes = np.zeros(ECHOES * len(model.felt))  # the last ECHOES normalised errors, newest first
        self.averages = np.full((len(WINDOWS), VIGOURS), np.nan)  # NaN until each signal is defined
        self.rates = 1.0 / np.asarray(WINDOWS)[:, None]
        self.inflation = model.inflation
        self.seen = 0
        self.state: Optional[np.ndarray] = None
        self.levels = [float("nan"), float("nan")]  # the surprise's and the memory check's averages

    def step(self, inputs: np.ndarray, state: Optional[np.ndarray] = None) -> tuple[float, float]:
        """The surprise and the memory check (`SurpriseModel.series`) after this normalised sample (F,), given the
        latent model's state after it (H,; None where it has none or the model no memory check)."""
        m, history = self.model, self.history
        history[-1] = inputs
        values = [float("nan"), float("nan")]
        if self.seen >= LAGS:
            row = self.features()
            residual = (inputs[self.felt] - m.predicted(row)[0]) / m.scale
            self.design[:-2] = np.log(np.maximum(self.averages - self.inflation, 0.0).ravel() + FLOOR)
            x = row[0, self.linear]
            length = float(x @ m.precision @ x) / len(x) - self.novelty_shift
            self.design[-2] = np.log(max(length, 0.0) + NOVELTY_FLOOR)  # `SurpriseModel.novelty`
            value, normal = m.values(residual[None], self.design[None], m.noise_floors(row), self.echoes[None])
            if self.seen >= WARM:
                values[0] = float(value[0])
            if m.innovation is not None:  # this error joins the echoes, newest first (`innovation.echoes`)
                self.echoes[len(residual):] = self.echoes[:-len(residual)].copy()
                self.echoes[:len(residual)] = normal[0]
        if m.memory is not None and self.state is not None and np.isfinite(self.state).all():
            values[1] = m.memory.step(self.state, inputs)
        for i, value in enumerate(values):
            if value == value:
                level = self.levels[i]
                self.levels[i] = value if level != level else level + (value - level) / SMOOTHING
        self.state = state
        self.seen += 1
        signals = self.signals()
        history[:-1] = history[1:].copy()
        if self.seen > 3:  # every signal defined: the averages' step in place
            self.averages *= 1.0 - self.rates
            self.averages += self.rates * signals
        else:
            self.averages = np.where(np.isnan(self.averages), signals, (1.0 - self.rates) * self.averages
                                     + self.rates * signals)
        return self.levels[0], self.levels[1]

    def features(self) -> np.ndarray:
        """(1, feature_width) `SurpriseModel.features` of the newest sample from the history, laid out in place."""
        history, row, f = self.history, self.row[0], self.model.channels
        lagged = LAGS * f
        row[:lagged] = history[LAGS - 1::-1].ravel()
        row[lagged:lagged + len(self.command)] = history[LAGS, self.command]
        z = np.concatenate([history[LAGS - 1], history[LAGS - 1] - history[LAGS - 2]])
        row[lagged + len(self.command):-1] = z[self.pairs[0]] * z[self.pairs[1]]
        return self.row

    def signals(self) -> np.ndarray:
        """`vigour_signals` of the newest sample, from the last three held."""
        out = np.full(VIGOURS, np.nan)
        newest, before, earlier = self.history[-1], self.history[-2], self.history[-3]
        if self.seen >= 2:
            first = newest[self.felt] - before[self.felt]
            out[1] = first @ first / len(first)
        if self.seen >= 3:
            second = (newest - before) - (before - earlier)
            felt, command = second[self.felt], second[self.command]
            out[0] = felt @ felt / len(felt)
            out[2] = command @ command / len(command) if len(command) else 0.0
        return out
