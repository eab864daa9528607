"""Imagination online: one stretch sample in, one imagined frame out, at a robot's control rate.

A robot's loop calls `step(sample)` once per sensor reading (every 10 ms at the default frame rate).
The window model keeps the last `history` samples and runs its LSTM over them; the stream model keeps
only its recurrent state and advances it by one sample. Either way the decoder then draws one latent
code: the same computation as a batch replay, frame for frame. With the paper's set-up
(`include_current` false) the samples up to k predict frame k+1, what the body will look like at the
next sample; with `include_current` they predict frame k.
"""

from collections import deque
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np
import torch

from softarm.learn.checkpoint import load_checkpoint
from softarm.learn.imaginer import Imaginer, Prediction


@dataclass(frozen=True)
class ImaginedFrame:
    frame: int                  # the frame index imagined
    probabilities: np.ndarray   # (H, W) pixel probabilities
    confidence: float           # in (0, 1]: how far to trust it (softarm.learn.imaginer.Prediction)


class StreamingImaginer:
    @classmethod
    def from_checkpoint(cls, path: Union[str, Path]) -> "StreamingImaginer":
        """The streamer of a checkpoint written by `softarm train`."""
        return cls(Imaginer.from_checkpoint(load_checkpoint(path)))

    def __init__(self, imaginer: Imaginer):
        self.imaginer = imaginer
        self._window: deque[np.ndarray] = deque(maxlen=imaginer.history)
        self._state: Optional[Any] = None  # the stream model's recurrent state
        self.samples = 0  # samples seen so far; the latest one is sample samples - 1

    @torch.inference_mode()
    def step(self, sample: np.ndarray) -> Optional[ImaginedFrame]:
        """Take the next sample (P readings, m); return the frame it lets the model imagine, or None until
        `history` samples have been seen (the first frame a batch replay imagines)."""
        imaginer = self.imaginer
        self.samples += 1
        frame = np.array([self.samples - 1 + imaginer.lead])
        if imaginer.model == "stream":  # the state advances with every sample, answered or not
            x = torch.from_numpy(imaginer.stretch_scaler.forward(np.asarray(sample, np.float64)[None, None]).astype(np.float32))
            latent, log_error, self._state = imaginer.lstm(x, self._state)
            prediction = Prediction(frame, latent[0].numpy(), log_error[0].numpy())
        else:
            self._window.append(np.asarray(sample, np.float64))
        if self.samples < imaginer.history:
            return None
        if imaginer.model == "window":
            prediction = imaginer.predict_windows(np.stack(self._window)[None], frame)
        return ImaginedFrame(int(frame[0]), imaginer.decode(prediction.latents)[0], float(prediction.confidence[0]))

    def reset(self) -> None:
        """Forget what was read (a new run or a gap in the readings)."""
        self._window.clear()
        self._state = None
        self.samples = 0
