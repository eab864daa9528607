"""Trivial answers that every imagination is judged against: the mean frame and ridge regressions.

A model is only worth its training if it beats predicting the average training frame, and a linear
map from the same input window to the same latent code.
"""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
import torch

from softarm.errors import CheckpointError


@dataclass(frozen=True)
class Baselines:
    """The trivial answers fitted on a training run, kept in its checkpoint so that any later
    evaluation (replay, the suite) scores them on the same frames as the model."""
    mean_frame: np.ndarray                 # (H, W) mean training frame, pixel probabilities
    ridge: tuple[np.ndarray, np.ndarray]   # (weights, bias): normalised input window -> normalised latent
    nodes: Optional[tuple[np.ndarray, np.ndarray]] = None  # the privileged ridge to node positions (node_ridge.py)

    def to_state(self) -> dict[str, torch.Tensor]:
        weights, bias = self.ridge
        state = {"mean_frame": torch.from_numpy(self.mean_frame.copy()),
                 "ridge_weights": torch.from_numpy(weights.copy()), "ridge_bias": torch.from_numpy(bias.copy())}
        if self.nodes is not None:
            state["node_weights"], state["node_bias"] = (torch.from_numpy(a.copy()) for a in self.nodes)
        return state

    @classmethod
    def from_checkpoint(cls, state: dict[str, Any]) -> "Baselines":
        if "baselines" not in state:
            raise CheckpointError("the checkpoint holds no baselines (it was trained by an older softarm or did not "
                                  "finish): train it again")
        b = state["baselines"]
        nodes = (b["node_weights"].numpy(), b["node_bias"].numpy()) if "node_weights" in b else None
        return cls(mean_frame=b["mean_frame"].numpy(), ridge=(b["ridge_weights"].numpy(), b["ridge_bias"].numpy()),
                   nodes=nodes)


def ridge_fit(inputs: np.ndarray, targets: np.ndarray, alpha: float = 1e-3) -> tuple[np.ndarray, np.ndarray]:
    """Least squares with an L2 penalty, from flattened inputs (M, ...) to targets (M, K): (weights, bias)."""
    x = inputs.reshape(len(inputs), -1).astype(np.float64)
    mean_x, mean_y = x.mean(0), targets.mean(0)
    xc, yc = x - mean_x, targets - mean_y
    weights = np.linalg.solve(xc.T @ xc + alpha * len(x) * np.eye(x.shape[1]), xc.T @ yc)
    return weights, mean_y - mean_x @ weights


def ridge_predict(model: tuple[np.ndarray, np.ndarray], inputs: np.ndarray) -> np.ndarray:
    """Targets (M, K) predicted for flattened inputs (M, ...) by a `ridge_fit` model."""
    weights, bias = model
    return inputs.reshape(len(inputs), -1) @ weights + bias
