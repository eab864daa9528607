"""Imagination online: one stretch sample in, one imagined frame out, at a robot's control rate.

A robot's loop calls `step(sample)` once per sensor reading (every 10 ms at the default frame rate).
The streamer keeps the last `history` samples, so each call runs the LSTM over one window and the
decoder over one latent code: the same computation as a batch replay, frame for frame. With the
paper's set-up (`include_current` false) the window of samples k-history+1 .. k predicts frame k+1,
what the body will look like at the next sample; with `include_current` it predicts frame k.
"""

from collections import deque
from pathlib import Path
from typing import Optional, Union

import numpy as np
import torch

from softarm.learn.checkpoint import load_checkpoint
from softarm.learn.imaginer import Imaginer


class StreamingImaginer:
    @classmethod
    def from_checkpoint(cls, path: Union[str, Path]) -> "StreamingImaginer":
        """The streamer of a checkpoint written by `softarm train`."""
        return cls(Imaginer.from_checkpoint(load_checkpoint(path)))

    def __init__(self, imaginer: Imaginer):
        self.imaginer = imaginer
        self._window: deque[np.ndarray] = deque(maxlen=imaginer.history)
        self._lead = 0 if imaginer.include_current else 1
        self.samples = 0  # samples seen so far; the latest one is sample samples - 1

    @torch.inference_mode()
    def step(self, sample: np.ndarray) -> Optional[tuple[int, np.ndarray]]:
        """Take the next sample (P readings, m); return (frame index, pixel probabilities (H, W)) of the frame
        its window predicts, or None until `history` samples have been seen."""
        self._window.append(np.asarray(sample, np.float64))
        self.samples += 1
        if len(self._window) < self.imaginer.history:
            return None
        window = np.stack(self._window)[None]
        latent = self.imaginer.latents(window)
        return self.samples - 1 + self._lead, self.imaginer.decode(latent)[0]

    def reset(self) -> None:
        """Forget the window (a new run or a gap in the readings)."""
        self._window.clear()
        self.samples = 0
