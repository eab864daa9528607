"""Surprise: what the body felt that its own command did not predict.

The forward model is the arm's expectation of its own feeling: a linear map from the last `LAGS` samples of
every input channel and the command of the next sample (the efference copy: the robot knows what it told its
motor) to the stretch it expects to feel next. Linear on purpose: the body's mechanics are close to linear over
one 10 ms step, so the map extrapolates to motions the corpus never showed, where a map from the latent model's
state (trained to draw the body, not to predict the stretch) erred by hundreds of its spreads.

How far a felt sample may stray depends on how the arm is moving: a prediction is sharper while the arm hangs
still than while it whips at a resonance. So each residual is divided by the spread the forward model expects
for it, a log-linear map (`spread`) from the arm's recent vigour (exponential averages of the squared first and
second differences of the stretch and of the command's second differences over `WINDOWS` samples, known before
the sample): the surprise is the mean over sensors of the squared residual in units of each sensor's residual
spread, divided by that expectation and smoothed over `SMOOTHING` samples. About 1 while the world leaves the
arm alone; an alarm fires while it exceeds a threshold set for a false-alarm rate on undisturbed motion.

Sensors noisier than those the model was fitted on (`heard_through`) would make every sample surprising. Their
white noise (and quantisation) is known, so its share is expected too: the residual's extra variance through the
forward model's weights is added to the expectation, and the noise's share of the vigour averages is taken off
them before they predict it.

NumPy only: the streamer's surprise costs two small matrix-vector products per sample.
"""

from dataclasses import dataclass, field, replace
from typing import Any, Optional

import numpy as np

from softarm.trust.memory_check import MemoryCheck

LAGS = 10            # samples of every input channel the forward model reads (100 ms at the default rate)
WINDOWS = (5.0, 50.0)  # samples: time constants of the vigour averages
SMOOTHING = 3.0      # samples: the surprise's exponential average (30 ms at the default rate)
FLOOR = 1e-6         # added to the vigour averages before their logarithm (normalised units squared)
VIGOURS = 3          # signals averaged per window: stretch's 2nd and 1st differences, command's 2nd difference


@dataclass(frozen=True)
class SurpriseModel:
    weights: np.ndarray    # (LAGS * F + C + 1, P): [inputs k, k - 1, ..., command k + 1, 1] -> stretch k + 1
    scale: np.ndarray      # (P,) each sensor's residual spread on undisturbed motion (normalised units)
    spread: np.ndarray     # (VIGOURS * len(WINDOWS) + 1,) log expected squared residual from the vigour after k
    threshold: float       # the alarm fires while the surprise exceeds it
    felt: tuple[int, ...]     # the columns of the normalised inputs that are felt (the stretch)
    command: tuple[int, ...]  # the columns that are the command, known one sample ahead
    memory: Optional[MemoryCheck] = None  # how well the latent model's state foresees the stretch (the confidence's)
    noise: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (P,) or empty: `heard_through`

    def heard_through(self, variance: np.ndarray) -> "SurpriseModel":
        """This model for readings whose felt columns carry `variance` (P,) more white noise (normalised units
        squared) than those it was fitted on: a property of the sensors read, so never saved with the model."""
        return replace(self, noise=np.asarray(variance, np.float64))

    @property
    def noise_floor(self) -> float:
        """The mean over sensors of the squared residual the extra noise adds, in units of each sensor's spread:
        the felt sample's own noise and that of every lagged felt input through its weight."""
        if not self.noise.size:
            return 0.0
        width = (self.weights.shape[0] - len(self.command) - 1) // LAGS
        rows = [lag * width + c for lag in range(LAGS) for c in self.felt]
        added = self.noise + np.tile(self.noise, LAGS) @ self.weights[rows] ** 2
        return float((added / self.scale ** 2).mean())

    @property
    def inflation(self) -> np.ndarray:
        """(VIGOURS,) what the extra noise adds to each vigour signal on average: the mean over sensors of its
        variance through the 2nd and the 1st difference (6 and 2 times it); none to the command's."""
        mean = float(self.noise.mean()) if self.noise.size else 0.0
        return np.array([6.0 * mean, 2.0 * mean, 0.0])

    def features(self, inputs: np.ndarray) -> np.ndarray:
        """(T - LAGS, LAGS * F + C + 1): what predicts each sample from LAGS on, from a normalised series (T, F)."""
        t = len(inputs)
        lagged = [inputs[LAGS - 1 - j:t - 1 - j] for j in range(LAGS)]
        return np.concatenate([*lagged, inputs[LAGS:, list(self.command)], np.ones((t - LAGS, 1))], axis=1)

    def residuals(self, inputs: np.ndarray) -> np.ndarray:
        """(T, P) each felt sample's residual in units of its sensor's spread; NaN for the first LAGS."""
        out = np.full((len(inputs), len(self.felt)), np.nan)
        if len(inputs) > LAGS:
            out[LAGS:] = (inputs[LAGS:, list(self.felt)] - self.features(inputs) @ self.weights) / self.scale
        return out

    def expected(self, inputs: np.ndarray) -> np.ndarray:
        """(T,) the squared residual the vigour before each sample leads to expect; NaN for the first."""
        out = np.full(len(inputs), np.nan)
        out[1:] = np.exp(vigour(inputs, self.felt, self.command, self.inflation)[:-1] @ self.spread) + self.noise_floor
        return out

    def series(self, inputs: np.ndarray, states: Optional[np.ndarray] = None) -> tuple[np.ndarray, np.ndarray]:
        """(T,) the surprise after each sample of a normalised series (T, F); NaN until the first prediction. And
        (T,) the memory check's residual, smoothed the same way, from the latent model's states (T, H) after each
        sample (all NaN without a memory check or states)."""
        squared = (self.residuals(inputs) ** 2).mean(axis=1)
        memory = (self.memory.residuals(states, inputs) if self.memory is not None and states is not None
                  else np.full(len(inputs), np.nan))
        return smoothed(squared / self.expected(inputs)), smoothed(memory)

    def online(self) -> "SurpriseReader":
        return SurpriseReader(self)

    def to_state(self) -> dict[str, Any]:
        return {"kind": "lagged", "lags": LAGS, "windows": list(WINDOWS), "smoothing": SMOOTHING,
                "weights": self.weights.tolist(), "scale": self.scale.tolist(), "spread": self.spread.tolist(),
                "threshold": self.threshold, "felt": list(self.felt), "command": list(self.command),
                **({"memory": self.memory.to_state()} if self.memory is not None else {})}

    @classmethod
    def from_state(cls, state: dict[str, Any]) -> "SurpriseModel":
        felt, command = tuple(int(i) for i in state["felt"]), tuple(int(i) for i in state["command"])
        memory = MemoryCheck.from_state(state["memory"], felt, command) if state.get("memory") else None
        return cls(np.asarray(state["weights"], np.float64), np.asarray(state["scale"], np.float64),
                   np.asarray(state["spread"], np.float64), float(state["threshold"]), felt, command, memory)

    @staticmethod
    def current(state: dict[str, Any]) -> bool:
        """Whether a checkpoint's surprise state is this softarm's kind (earlier ones read the latent state)."""
        settings = [state.get(key) for key in ("kind", "lags", "windows", "smoothing")]
        plain = all(isinstance(value, (str, int, float, list)) for value in settings)
        return plain and settings == ["lagged", LAGS, list(WINDOWS), SMOOTHING]


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


class SurpriseReader:
    """The surprise sample by sample, in preallocated arrays (a robot's loop calls it every 10 ms): the last LAGS
    samples as the forward model's features, the vigour averages, the latent model's last state and the two
    smoothed values."""

    def __init__(self, model: SurpriseModel):
        self.model = model
        self.felt, self.command = np.array(model.felt, int), np.array(model.command, int)
        self.width = (model.weights.shape[0] - len(model.command) - 1) // LAGS  # input channels F
        self.features = np.zeros(model.weights.shape[0])  # [sample k, k - 1, ..., k - LAGS + 1, command, 1]
        self.features[-1] = 1.0
        self.vigour = np.ones(VIGOURS * len(WINDOWS) + 1)
        self.averages = np.full((len(WINDOWS), VIGOURS), np.nan)  # NaN until each signal is defined
        self.rates = 1.0 / np.asarray(WINDOWS)[:, None]
        self.inflation, self.floor = model.inflation, model.noise_floor
        self.seen = 0
        self.state: Optional[np.ndarray] = None
        self.levels = [float("nan"), float("nan")]  # the surprise's and the memory check's averages

    def step(self, inputs: np.ndarray, state: Optional[np.ndarray] = None) -> tuple[float, float]:
        """The surprise and the memory check (`SurpriseModel.series`) after this normalised sample (F,), given the
        latent model's state after it (H,; None where it has none or the model no memory check)."""
        m, x, width = self.model, self.features, self.width
        values = [float("nan"), float("nan")]
        if self.seen >= LAGS:
            x[LAGS * width:-1] = inputs[self.command]
            residual = (inputs[self.felt] - x @ m.weights) / m.scale
            self.vigour[:-1] = np.log(np.maximum(self.averages - self.inflation, 0.0).ravel() + FLOOR)
            values[0] = (float(residual @ residual) / len(residual)
                         / (float(np.exp(self.vigour @ m.spread)) + self.floor))
        if m.memory is not None and self.state is not None and np.isfinite(self.state).all():
            values[1] = m.memory.step(self.state, inputs)
        for i, value in enumerate(values):
            if value == value:
                level = self.levels[i]
                self.levels[i] = value if level != level else level + (value - level) / SMOOTHING
        self.state = state
        x[width:LAGS * width] = x[:(LAGS - 1) * width].copy()
        x[:width] = inputs
        self.seen += 1
        signals = self.signals()
        if self.seen > 3:  # every signal defined: the averages' step in place
            self.averages *= 1.0 - self.rates
            self.averages += self.rates * signals
        else:
            self.averages = np.where(np.isnan(self.averages), signals, (1.0 - self.rates) * self.averages
                                     + self.rates * signals)
        return self.levels[0], self.levels[1]

    def signals(self) -> np.ndarray:
        """`vigour_signals` of the newest sample, from the last three held in the features."""
        x, w = self.features, self.width
        out = np.full(VIGOURS, np.nan)
        newest, before, earlier = x[:w], x[w:2 * w], x[2 * w:3 * w]
        if self.seen >= 2:
            first = newest[self.felt] - before[self.felt]
            out[1] = first @ first / len(first)
        if self.seen >= 3:
            second = (newest - before) - (before - earlier)
            felt, command = second[self.felt], second[self.command]
            out[0] = felt @ felt / len(felt)
            out[2] = command @ command / len(command) if len(command) else 0.0
        return out
