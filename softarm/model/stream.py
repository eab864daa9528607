"""Latent models with memory: a recurrent layer reads the stream sample by sample and carries its state from
the first sample on, so a motion felt seconds ago still shapes today's answer. Every sample's state
predicts a latent. Trained by truncated back-propagation through time (`pieces`), gradients clipped.

`StreamLSTM` is the default model; `StreamGRU` is the same with a GRU layer (fewer weights, no cell state).
"""

from functools import partial
from typing import Any, Callable, Iterator, Optional, Sequence

import numpy as np
import torch
from torch import nn

from softarm.config import TrainConfig
from softarm.model import pieces
from softarm.model.device import array_of, tensor_on
from softarm.model.latent import OnlineReader, Order, Step, StepLoss, TrainingSeries
from softarm.model.prediction import Prediction
from softarm.model.recurrent import RecurrentModel, detached

STREAMS = 64  # series read side by side when answering


class StreamModel(RecurrentModel):
    clip_norm = 1.0

    def forward(self, samples: torch.Tensor, state: Any = None) -> tuple[torch.Tensor, torch.Tensor, Any]:
        """(B, T, P) samples, from `state` (None: the stream's start) -> latents (B, T, K), their log squared
        errors (B, T, K) and the state after the last sample."""
        states, state = self.rnn(samples, state)
        return self.head(states), self.error(states), state

    @torch.inference_mode()
    def answer(self, series: Sequence[np.ndarray]) -> list[Prediction]:
        """Series of equal length are read side by side, STREAMS at a time."""
        out: list[Optional[Prediction]] = [None] * len(series)
        for length in sorted({len(s) for s in series}):
            same = [i for i, s in enumerate(series) if len(s) == length]
            for first in range(0, len(same), STREAMS):
                group = same[first:first + STREAMS]
                for i, prediction in zip(group, self._answer_side_by_side(np.stack([series[i] for i in group]))):
                    out[i] = prediction
        return out

    def _answer_side_by_side(self, series: np.ndarray) -> list[Prediction]:
        """(S, T, P) series of one length, each read from its first sample."""
        targets = np.arange(self.first_frame, series.shape[1])
        latents, log_error, _ = self(tensor_on(series, self.device))
        samples = targets - self.lead
        latents, log_error = array_of(latents.float()), array_of(log_error.float())  # a bf16 pass (validation) too
        return [Prediction(targets, latents[s, samples], log_error[s, samples]) for s in range(len(series))]

    def online(self) -> OnlineReader:
        return StreamReader(self)

    def latents_at(self, series: torch.Tensor, samples: torch.Tensor) -> torch.Tensor:
        return self.head(self.rnn(series[None])[0][0, samples])

    @torch.inference_mode()
    def states(self, series: np.ndarray) -> np.ndarray:
        return array_of(self.rnn(tensor_on(series[None], self.device))[0][0].double())

    @classmethod
    def steps_per_epoch(cls, train_ends: Sequence[int], train: TrainConfig,
                        seen: Sequence[Optional[np.ndarray]] = ()) -> int:
        return pieces.steps_per_epoch(train_ends, train.streams, train.sequence, train.sequence, train.lead)

    def epoch(self, series: Sequence[TrainingSeries], order: Order) -> Callable[[int], Iterator[Step]]:
        """Every group of pieces in a shuffled order, each read chunk by chunk from a fresh state that carries
        over (detached) from chunk to chunk."""
        t = self.settings
        every = pieces.groups(series, t.streams, t.sequence, self.lead, self.device)  # on the device once

        def epoch(number: int) -> Iterator[Step]:
            for g in order(len(every), number).tolist():
                carried: list[Any] = [None]
                for samples, targets, scored in every[g].chunks(t.sequence):
                    if not scored.any():
                        with torch.no_grad():
                            carried[0] = self(samples, carried[0])[2]
                        continue
                    yield partial(self._chunk_step, carried, samples, targets, scored)

        return epoch

    def _chunk_step(self, carried: list[Any], samples: torch.Tensor, targets: torch.Tensor,
                    scored: torch.Tensor) -> StepLoss:
        """One chunk from the carried state, which it then replaces (detached: gradients stop here)."""
        states, state = self.rnn(samples, carried[0])
        carried[0] = detached(state)
        return self.trained_loss(states[scored], targets[scored])

    @classmethod
    def dummy_batch(cls, train: TrainConfig, inputs: int) -> torch.Tensor:
        return torch.zeros(train.streams, train.sequence, inputs)


class StreamLSTM(StreamModel):
    core = nn.LSTM


class StreamGRU(StreamModel):
    core = nn.GRU


class StreamReader(OnlineReader):
    """The recurrent state alone, advanced by one sample per step, in NumPy (`softarm.model.cells`: a step of the
    torch layer costs five times as much at one sample)."""

    def __init__(self, model: StreamModel):
        self.model = model
        self.cell = model.cell()
        self.readout = model.readout()
        self.samples = 0

    def step(self, sample: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
        state = self.cell.step(sample)
        self.samples += 1  # the state advances with every sample, answered or not
        self.state_vector = state.astype(np.float64)
        if self.samples < self.model.history:
            return None
        return self.readout(state)
