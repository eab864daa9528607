"""A latent model's answers for some frames, and the confidence it has in each (NumPy only: importing it loads
no network)."""

from dataclasses import dataclass
from typing import Sequence

import numpy as np


@dataclass(frozen=True)
class Prediction:
    """The latent answers for some frames of one recording (or several, one after another)."""
    targets: np.ndarray     # (M,) frame indices, or (M, 2) (recording, frame) pairs
    latents: np.ndarray     # (M, K) normalised kept latent features
    log_error: np.ndarray   # (M, K) the model's own estimate of each feature's log squared error

    @property
    def confidence(self) -> np.ndarray:
        """(M,) in (0, 1]: 1 / (1 + the predicted mean squared error of the normalised latent); 0.5 means the
        model expects to be as far off as a guess of the mean frame's code."""
        return 1.0 / (1.0 + np.exp(self.log_error).mean(axis=1))

    def take(self, keep: np.ndarray) -> "Prediction":
        return Prediction(self.targets[keep], self.latents[keep], self.log_error[keep])

    @staticmethod
    def join(parts: Sequence["Prediction"]) -> "Prediction":
        return Prediction(*(np.concatenate(arrays) for arrays in zip(*((p.targets, p.latents, p.log_error)
                                                                       for p in parts))))
