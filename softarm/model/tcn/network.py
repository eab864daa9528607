"""The causal temporal convolution network: dilated convolutions, each sample's state computed from that sample
and the RECEPTIVE - 1 before it, nothing later and nothing older.

Its memory is a fixed window, as the paper's window model's, but 2.56 s long instead of 60 ms; unlike the stream
models it needs no state carried from the stream's first sample, so every sample of a series is read at once in
training and replay. Its shape is `shape`'s (KERNEL, DILATIONS); its width is `train.lstm_hidden`, the state
every head, the surprise and adaptation read.
"""

from functools import partial
from typing import Callable, Iterator, Optional, Sequence

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from softarm.config import TrainConfig
from softarm.model.device import array_of, tensor_on
from softarm.model.latent import LatentModel, OnlineReader, Order, Step, StepLoss, TrainingSeries
from softarm.model.prediction import Prediction
from softarm.model.tcn.reader import TcnReader
from softarm.model.tcn.rows import ROW, cut, per_step, row_steps
from softarm.model.tcn.shape import DILATIONS, KERNEL, RECEPTIVE


class CausalTCN(LatentModel):
    """Layer 0 maps the inputs to `width` channels; every later layer adds its output to its input (a residual
    stack). Each layer is a dilated convolution followed by a ReLU, padded on the left only: causal."""

    def make_core(self, inputs: int, width: int) -> None:
        self.layers = nn.ModuleList(nn.Conv1d(inputs if i == 0 else width, width, KERNEL, dilation=d)
                                    for i, d in enumerate(DILATIONS))

    def features(self, samples: torch.Tensor) -> torch.Tensor:
        """(B, T, P) samples -> (B, T, H) states; a series starts from zeros before its first sample."""
        x = samples.transpose(1, 2)
        for i, (conv, dilation) in enumerate(zip(self.layers, DILATIONS)):
            y = torch.relu(conv(F.pad(x, ((KERNEL - 1) * dilation, 0))))
            x = y if i == 0 else x + y
        return x.transpose(1, 2)

    def forward(self, samples: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, T, P) -> latents (B, T, K) and their log squared errors (B, T, K)."""
        states = self.features(samples)
        return self.head(states), self.error(states)

    @torch.inference_mode()
    def answer(self, series: Sequence[np.ndarray]) -> list[Prediction]:
        """Each series read whole, one at a time (the states of many long series side by side would not fit)."""
        out = []
        for s in series:
            latents, log_error = (array_of(a[0].float()) for a in self(tensor_on(s[None], self.device)))
            targets = np.arange(self.first_frame, len(s))
            out.append(Prediction(targets, latents[targets - self.lead], log_error[targets - self.lead]))
        return out

    def online(self) -> OnlineReader:
        return TcnReader(self)

    def latents_at(self, series: torch.Tensor, samples: torch.Tensor) -> torch.Tensor:
        return self.head(self.features(series[None])[0, samples])

    @torch.inference_mode()
    def states(self, series: np.ndarray) -> np.ndarray:
        return array_of(self.features(tensor_on(series[None], self.device))[0].double())

    @classmethod
    def steps_per_epoch(cls, train_ends: Sequence[int], train: TrainConfig,
                        seen: Sequence[Optional[np.ndarray]] = ()) -> int:
        return row_steps(train_ends, seen, train)

    def epoch(self, series: Sequence[TrainingSeries], order: Order) -> Callable[[int], Iterator[Step]]:
        """Shuffled batches of rows (`rows.cut`), each row's samples read at once."""
        batch = cut(series, self.settings, RECEPTIVE, self.device)  # on the device once, for every epoch

        def step(index: torch.Tensor) -> StepLoss:
            index = index.to(batch.samples.device)
            scored = batch.scored[index]
            return self.trained_loss(self.features(batch.samples[index])[scored], batch.targets[index][scored])

        size = per_step(self.settings)
        return lambda number: (partial(step, i) for i in torch.split(order(len(batch.samples), number), size))

    @classmethod
    def dummy_batch(cls, train: TrainConfig, inputs: int) -> torch.Tensor:
        return torch.zeros(per_step(train), RECEPTIVE - 1 + ROW, inputs)
