"""Realistic sensor imperfections, applied to ideal stretch readings where they are read, not recorded.

Each imperfection draws from its own child of one generator seeded by (seed, stream), so switching one
on or off leaves the realisation of the others unchanged, and a study can vary one at a time.
"""

from dataclasses import dataclass, fields

import numpy as np

from softarm.config.schema import SensingConfig
from softarm.errors import ConfigError


@dataclass(frozen=True)
class SensorModel:
    noise: float           # white noise: standard deviation of each sample, m
    bias: float            # each sensor's constant offset is drawn from N(0, bias^2), m
    drift: float           # random walk: standard deviation of its growth per sqrt(second), m/sqrt(s)
    quantisation: float    # readings are rounded to multiples of this step, m (0: not rounded)
    dropout_sensor: int    # this sensor (a column of the readings) is stuck from dropout_time on (-1: none)
    dropout_time: float    # s
    seed: int

    @classmethod
    def from_config(cls, sensing: SensingConfig) -> "SensorModel":
        """The imperfections of a [sensing] section: every key but pairs."""
        return cls(**{f.name: getattr(sensing, f.name) for f in fields(cls)})

    @property
    def ideal(self) -> bool:
        """Nothing is applied: the readings are the recorded ones."""
        return (self.noise == 0 and self.bias == 0 and self.drift == 0 and self.quantisation == 0
                and self.dropout_sensor < 0)

    @property
    def white_variance(self) -> float:
        """The variance, m^2, of the sample-to-sample independent part of the error: the white noise's and the
        rounding's (a step q adds q^2 / 12); bias and drift change too slowly to count."""
        return self.noise ** 2 + self.quantisation ** 2 / 12.0

    def apply(self, stretch: np.ndarray, times: np.ndarray, stream: int = 0) -> np.ndarray:
        """Imperfect (T, P) float64 readings from ideal ones (T, P) m sampled at times (T,) s.

        In order: bias, drift, white noise, quantisation, dropout. `stream` gives each recording its own
        realisation (callers pass, for example, the recording's simulation seed).
        """
        out = np.array(stretch, np.float64)
        if self.ideal:
            return out
        times = np.asarray(times, np.float64)
        if out.ndim != 2 or times.shape != (out.shape[0],):
            raise ValueError(f"readings {out.shape} and times {times.shape} must be (T, P) and (T,)")
        bias_rng, drift_rng, noise_rng = np.random.default_rng([self.seed, stream]).spawn(3)
        n_sensors = out.shape[1]
        if self.bias > 0:
            out += bias_rng.normal(0.0, self.bias, n_sensors)
        if self.drift > 0:
            scale = self.drift * np.sqrt(np.diff(times))[:, None]  # the walk's standard deviation over each step
            out[1:] += np.cumsum(drift_rng.normal(0.0, 1.0, (len(scale), n_sensors)) * scale, axis=0)
        if self.noise > 0:
            out += noise_rng.normal(0.0, self.noise, out.shape)
        if self.quantisation > 0:
            out = np.round(out / self.quantisation) * self.quantisation
        if self.dropout_sensor >= 0:
            self._drop_out(out, times)
        return out

    def _drop_out(self, out: np.ndarray, times: np.ndarray) -> None:
        """From the first sample at or after dropout_time, the sensor repeats the last value it read before it."""
        if self.dropout_sensor >= out.shape[1]:
            raise ConfigError(f"config key 'sensing.dropout_sensor' = {self.dropout_sensor} is out of range: "
                              f"the readings have sensors 0..{out.shape[1] - 1}")
        start = int(np.searchsorted(times, self.dropout_time, side="left"))
        if start < len(times):
            out[start:, self.dropout_sensor] = out[max(start - 1, 0), self.dropout_sensor]


IMPERFECTIONS = tuple(f.name for f in fields(SensorModel))  # the [sensing] keys but pairs


def parse_imperfections(text: str) -> dict[str, float]:
    """'noise=2e-5,drift=1e-6' -> {"noise": 2e-05, "drift": 1e-06}: a sensor model given on a command line.

    The keys are those of the [sensing] config section but `pairs` (the network was built for its pairs).
    """
    out: dict[str, float] = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or key not in IMPERFECTIONS:
            raise ConfigError(f"--sensor-noise {item!r}: give KEY=VALUE with KEY one of {', '.join(IMPERFECTIONS)}")
        try:
            number = float(value)
        except ValueError:
            raise ConfigError(f"--sensor-noise {item!r}: {value.strip()!r} is not a number") from None
        out[key] = int(number) if key in ("dropout_sensor", "seed") and number.is_integer() else number
    return out
