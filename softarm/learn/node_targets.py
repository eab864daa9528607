"""Node positions as an auxiliary target of the latent model (`train.node_target`).

A simulated recording knows where every node was; a head on the latent model's recurrent state that must
say so asks that state to hold the body's shape, not only what the autoencoder's code needs. The
positions are a training signal only: no model reads them, and no answer comes from that head.
"""

import numpy as np

from softarm.errors import ConfigError
from softarm.learn.dataset import Dataset


def node_targets(data: Dataset) -> list[np.ndarray]:
    """Every recording's node positions as (T, 2N) float32 targets: each coordinate less its mean over the
    training frames, divided by one spread for all coordinates (so that the nearly still top row is not
    magnified into noise)."""
    require_positions(data)
    flat = [s.positions.reshape(len(s.positions), -1).astype(np.float64) for s in data.sequences]
    training = np.concatenate([f[slice(*s.segment("train"))] for f, s in zip(flat, data.sequences)])
    mean = training.mean(axis=0)
    spread = max(float((training - mean).std()), 1e-9)
    return [((f - mean) / spread).astype(np.float32) for f in flat]


def node_outputs(data: Dataset, weight: float) -> int:
    """Outputs of the node head: two per node when the target is on, none otherwise."""
    if weight <= 0:
        return 0
    require_positions(data)
    return 2 * data.sequences[0].positions.shape[1]


def require_positions(data: Dataset) -> None:
    missing = [s.name for s in data.sequences if s.positions is None]
    if missing:
        raise ConfigError(f"train.node_target needs node positions, which {missing[0]} does not hold: "
                          "set train.node_target = 0 for recordings without them")
