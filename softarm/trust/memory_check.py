"""How well the latent model's memory foresees what the arm feels next: the calibrated confidence's best clue.

The latent model's recurrent state after sample k is the arm's memory of how its body moved; with the command of
sample k + 1, a linear map from that state predicts the stretch of sample k + 1. Where the memory has lost track of
the body (a motion the corpus never showed, a touch), this prediction errs, and so does the imagination drawn from
the same state: its smoothed residual ranks the imagined frames by their error better than anything else the model
knows without a camera. It is no alarm: the residual also grows with vigorous motion the memory does follow (the
surprise, `softarm.trust.surprise`, divides that out).
"""

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class MemoryCheck:
    weights: np.ndarray       # (H + C + 1, P): [state after sample k, command of sample k + 1, 1] -> stretch k + 1
    scale: np.ndarray         # (P,) each sensor's residual spread on held-out undisturbed motion (normalised units)
    felt: tuple[int, ...]     # the felt columns of the normalised inputs
    command: tuple[int, ...]  # the command columns

    def features(self, states: np.ndarray, next_inputs: np.ndarray) -> np.ndarray:
        return np.concatenate([states, next_inputs[:, list(self.command)], np.ones((len(states), 1))], axis=1)

    def residuals(self, states: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """(T,) the mean over sensors of each sample's squared residual against the prediction from the state
        before it, in units of the sensor's spread (NaN where that state is not known: the first sample)."""
        out = np.full(len(inputs), np.nan)
        if len(inputs) > 1:
            expected = self.features(states[:-1], inputs[1:]) @ self.weights
            out[1:] = (((inputs[1:, list(self.felt)] - expected) / self.scale) ** 2).mean(axis=1)
        return out

    def step(self, state: np.ndarray, inputs: np.ndarray) -> float:
        """One sample's value of `residuals`, given the state before it (H,)."""
        hidden = len(state)
        expected = (state @ self.weights[:hidden] + inputs[list(self.command)] @ self.weights[hidden:-1]
                    + self.weights[-1])
        return float((((inputs[list(self.felt)] - expected) / self.scale) ** 2).mean())

    def to_state(self) -> dict[str, Any]:
        return {"weights": self.weights, "scale": self.scale}

    @classmethod
    def from_state(cls, state: dict[str, Any], felt: tuple[int, ...], command: tuple[int, ...]) -> "MemoryCheck":
        return cls(np.asarray(state["weights"], np.float64), np.asarray(state["scale"], np.float64), felt, command)

