"""What the forward model's last errors did not foresee. On a motion new to it, the forward model errs the same way
for many samples in a row (out of fold on the corpus, each sensor's error correlates 0.8 with the one before), so
a push's few hundredths of a spread drown in an error that was already there. The errors of the last `ECHOES`
samples predict much of the next one; what they leave, the innovation, is what changed at this sample: a push, a
touch, the first sample of a load. A load that stays is foreseen again after a few samples, so the surprise keeps
the plain error beside the innovation (docs/model.md, Surprise).

The errors here are the forward model's residuals in units of their expected spread (`SurpriseModel`), so a
vigorous motion does not weigh more in the fit than a quiet one.
"""

from dataclasses import dataclass
from functools import cached_property
from typing import Any, Optional

import numpy as np

ECHOES = 64  # samples of past errors the next error is predicted from (640 ms at the default rate)


def echoes(errors: np.ndarray) -> np.ndarray:
    """(T, ECHOES * P) the errors (T, P) of the ECHOES samples before each, newest first; 0 where none was made
    (before the first prediction), as the streamer starts."""
    t, p = errors.shape
    known = np.nan_to_num(errors, nan=0.0)
    out = np.zeros((t, ECHOES * p))
    for j in range(1, min(ECHOES, t - 1) + 1):
        out[j:, (j - 1) * p:j * p] = known[:t - j]
    return out


@dataclass(frozen=True)
class Innovation:
    persistence: np.ndarray  # (ECHOES * P, P): the errors of samples k - 1, ..., k - ECHOES -> the error of k
    scale: np.ndarray        # (P,) each sensor's innovation spread on undisturbed motion, out of fold
    spread: np.ndarray       # (DESIGN,) log expected squared innovation from the surprise's design row

    def news(self, errors: np.ndarray, lagged: Optional[np.ndarray] = None) -> np.ndarray:
        """(T, P) each error less what the errors before it foresee, in units of each sensor's innovation spread;
        NaN where the error is. `lagged`: the errors before each row (`echoes`) where the rows are not a whole
        series (the streamer's one sample)."""
        before = echoes(errors) if lagged is None else lagged
        return (errors - before @ self.persistence) / self.scale

    @cached_property
    def noise_gain(self) -> np.ndarray:
        """(P, P): entry (q, p) is how much of sensor q's error variance, white from sample to sample, reaches
        sensor p's innovation (itself once, and through every echo's weight squared), over p's spread squared."""
        p = len(self.scale)
        through = (self.persistence ** 2).reshape(ECHOES, p, p).sum(axis=0) + np.eye(p)
        return through / self.scale ** 2

    def expected(self, design: np.ndarray, motion: np.ndarray, noise: np.ndarray) -> np.ndarray:
        """(T,) the expected mean squared innovation: the spread map's value from the design rows (T, DESIGN) for
        the motion's share of the error (`motion` (T,), 1 without extra noise), plus what the extra sensor noise
        adds (`noise` (T, P), each sensor's share of the error), which the echoes cannot foresee."""
        expected = np.exp(design @ self.spread) * motion
        return expected + (noise @ self.noise_gain).mean(axis=1) if noise.any() else expected

    def to_state(self) -> dict[str, Any]:
        return {"echoes": ECHOES, "persistence": self.persistence, "scale": self.scale, "spread": self.spread}

    @classmethod
    def from_state(cls, state: dict[str, Any]) -> "Innovation":
        return cls(np.asarray(state["persistence"], np.float64), np.asarray(state["scale"], np.float64),
                   np.asarray(state["spread"], np.float64))
