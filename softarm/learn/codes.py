"""Latent codes of every recording, encoded once by the trained autoencoder and then indexed.

Sixteen numbers a frame replace stacked copies of the target frames for every later use: the latent
model's training targets, the scalers, the ridge baseline and the metrics.
"""

import numpy as np

from softarm.learn.dataset import Dataset
from softarm.model.autoencoder import Autoencoder, encode_frames


class LatentCodes:
    def __init__(self, autoencoder: Autoencoder, data: Dataset):
        autoencoder.eval()
        self._codes = [encode_frames(autoencoder, seq.frames) for seq in data.sequences]

    def of(self, targets: np.ndarray) -> np.ndarray:
        """Raw codes (M, F) of (recording, frame) targets (M, 2), in the order `Dataset.windows` lists them."""
        return np.concatenate([self._codes[n][targets[targets[:, 0] == n, 1]] for n in range(len(self._codes))])

    def segment(self, data: Dataset, segment: str) -> np.ndarray:
        """Raw codes of every frame of a segment, all recordings in order."""
        return np.concatenate([self._codes[n][slice(*seq.segment(segment))] for n, seq in enumerate(data.sequences)])

    def recording(self, n: int) -> np.ndarray:
        """Raw codes (T, F) of every frame of recording n."""
        return self._codes[n]
