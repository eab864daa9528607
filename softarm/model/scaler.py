"""Latent feature filter and normalisation, fitted on training data only, stored in the checkpoint.

The paper drops latent features that do not change over the training frames (its "high pass
filter"): they carry nothing a latent model could predict. The kept features, and every input
channel's signals, are normalised to zero mean and unit variance with training statistics.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np
import torch


@dataclass(frozen=True)
class Scaler:
    """x -> (x[..., keep] - mean) / std, and back (dropped features come back as their training mean)."""
    keep: np.ndarray   # (F,) bool
    mean: np.ndarray   # (F,) over all features, float64
    std: np.ndarray    # (F,) over all features, float64 (1 where a feature is constant)

    @classmethod
    def fit(cls, data: np.ndarray, min_relative_std: Optional[float] = None) -> "Scaler":
        """Statistics of data (M, F); features with std below min_relative_std x the largest std are
        dropped (None keeps every feature, e.g. every input a latent model is built for)."""
        data = data.astype(np.float64)
        mean, std = data.mean(axis=0), data.std(axis=0)
        if min_relative_std is None:
            keep = np.ones(len(std), bool)
        else:
            keep = std > min_relative_std * std.max() if std.max() > 0 else np.zeros(len(std), bool)
        return cls(keep=keep, mean=mean, std=np.where(std > 0, std, 1.0))

    @property
    def kept(self) -> int:
        return int(self.keep.sum())

    def forward(self, data: np.ndarray) -> np.ndarray:
        return ((data - self.mean) / self.std)[..., self.keep]

    def inverse(self, normalised: np.ndarray) -> np.ndarray:
        out = np.broadcast_to(self.mean, (*normalised.shape[:-1], len(self.mean))).copy()
        out[..., self.keep] = normalised * self.std[self.keep] + self.mean[self.keep]
        return out

    def to_state(self) -> dict[str, torch.Tensor]:
        """Tensors only, so the checkpoint loads with torch.load(weights_only=True)."""
        return {"keep": torch.from_numpy(self.keep.copy()), "mean": torch.from_numpy(self.mean.copy()),
                "std": torch.from_numpy(self.std.copy())}

    @classmethod
    def from_state(cls, state: dict[str, torch.Tensor]) -> "Scaler":
        return cls(keep=state["keep"].numpy().astype(bool), mean=state["mean"].numpy().astype(np.float64),
                   std=state["std"].numpy().astype(np.float64))
