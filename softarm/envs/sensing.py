"""The [sensing] imperfections applied sample by sample to many arms at once, as a controller reads them.

The same imperfections, in the same order, as `softarm.sense.imperfections.SensorModel.apply` gives a recording
(bias, drift, white noise, quantisation, dropout), drawn from each arm's own generator so that an arm of a vector
env reads what a single env of the same seed reads. Bias and drift restart with each episode; dropout counts
from the episode's start.
"""

import numpy as np

from softarm.sense.imperfections import SensorModel


class StepSensing:
    def __init__(self, model: SensorModel, arms: int, sensors: int, frame_dt: float):
        self.model, self.frame_dt = model, frame_dt
        self.bias = np.zeros((arms, sensors))
        self.drift = np.zeros((arms, sensors))
        self.last = np.zeros((arms, sensors))

    def start(self, arms: np.ndarray, rngs: list) -> None:
        """New episodes for the given arms: a new bias, no drift yet."""
        for a in arms:
            self.bias[a] = rngs[a].normal(0.0, self.model.bias, self.bias.shape[1]) if self.model.bias > 0 else 0.0
            self.drift[a] = 0.0

    def read(self, ideal: np.ndarray, arms: np.ndarray, steps: np.ndarray, rngs: list) -> np.ndarray:
        """(k, P) readings of the given arms from their ideal stretch (k, P), m, at their steps into the episode
        (k,), drawing from their generators (k)."""
        m = self.model
        out = ideal + self.bias[arms]
        if m.drift > 0:
            for k, a in enumerate(arms):
                if steps[k] > 0:  # the walk starts at the episode's first sample
                    self.drift[a] += rngs[k].normal(0.0, m.drift * np.sqrt(self.frame_dt), out.shape[1])
            out = out + self.drift[arms]
        if m.noise > 0:
            out = out + np.stack([rng.normal(0.0, m.noise, out.shape[1]) for rng in rngs])
        if m.quantisation > 0:
            out = np.round(out / m.quantisation) * m.quantisation
        if m.dropout_sensor >= 0:
            stuck = (steps > 0) & (steps * self.frame_dt >= m.dropout_time)
            out[stuck, m.dropout_sensor] = self.last[arms][stuck, m.dropout_sensor]
            self.last[arms] = out
        return out
