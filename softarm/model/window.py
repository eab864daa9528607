"""The paper's latent model: an LSTM over the last `history` input samples, started afresh for every
window; its last state predicts the latent. It knows what the last 60 ms felt like, nothing older."""

import math
from collections import deque
from functools import partial
from typing import Callable, Iterator, Optional, Sequence

import numpy as np
import torch

from softarm.config import TrainConfig
from softarm.model.autoencoder import in_batches
from softarm.model.device import array_of, tensor_on
from softarm.model.input_windows import input_windows, window_count
from softarm.model.latent import OnlineReader, Order, Step, TrainingSeries
from softarm.model.prediction import Prediction
from softarm.model.recurrent import RecurrentModel


class WindowLSTM(RecurrentModel):
    def forward(self, windows: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, history, P) -> predicted latents (B, K) and their log squared errors (B, K)."""
        states, _ = self.rnn(windows)
        last = states[:, -1]
        return self.head(last), self.error(last)

    def answer(self, series: Sequence[np.ndarray]) -> list[Prediction]:
        return [self.answer_windows(*input_windows(s, self.history, self.lead)) for s in series]

    def answer_segments(self, series: Sequence[np.ndarray], bounds: Sequence[tuple[int, int]]) -> Prediction:
        """Only the segments' own windows are read: this model remembers nothing older."""
        windows, targets = [], []
        for n, (s, (start, end)) in enumerate(zip(series, bounds)):
            w, k = input_windows(s, self.history, self.lead, start, end)
            windows.append(w)
            targets.append(np.stack([np.full(len(k), n), k], axis=1))
        return self.answer_windows(np.concatenate(windows), np.concatenate(targets))

    @torch.inference_mode()
    def answer_windows(self, windows: np.ndarray, targets: np.ndarray) -> Prediction:
        """The answers for normalised windows (M, history, P) and the frames they imagine."""
        latents, log_error = in_batches(self, tensor_on(windows, self.device))
        return Prediction(targets, array_of(latents.float()), array_of(log_error.float()))

    def online(self) -> OnlineReader:
        return WindowReader(self)

    def latents_at(self, series: torch.Tensor, samples: torch.Tensor) -> torch.Tensor:
        windows = series[samples[:, None] - self.history + 1 + torch.arange(self.history, device=series.device)]
        return self(windows)[0]

    @torch.inference_mode()
    def states(self, series: np.ndarray) -> np.ndarray:
        """The last state of the window that ends at each sample."""
        out = np.full((len(series), self.settings.lstm_hidden), np.nan)
        windows, _ = input_windows(series, self.history, 0)
        last = lambda w: self.rnn(w)[0][:, -1]  # noqa: E731
        out[self.history - 1:] = array_of(in_batches(last, tensor_on(windows, self.device)).double())
        return out

    @classmethod
    def steps_per_epoch(cls, train_ends: Sequence[int], train: TrainConfig,
                        seen: Sequence[Optional[np.ndarray]] = ()) -> int:
        first = train.history - 1 + train.lead  # the frame the first window imagines
        masks = list(seen) or [None] * len(train_ends)
        pairs = sum(window_count(end, train.history, train.lead) if mask is None else int(mask[first:end].sum())
                    for end, mask in zip(train_ends, masks))
        return math.ceil(pairs / train.batch_lstm)

    def epoch(self, series: Sequence[TrainingSeries], order: Order) -> Callable[[int], Iterator[Step]]:
        """Shuffled batches of (window, latent of the frame it imagines) pairs of every training segment."""
        pairs = [input_windows(s.inputs, self.history, self.lead, 0, s.train_end) for s in series]
        pairs = [(w, k) if s.seen is None else (w[s.seen[k]], k[s.seen[k]]) for s, (w, k) in zip(series, pairs)]
        x = tensor_on(np.concatenate([w for w, _ in pairs]), self.device)  # on the device once, for every epoch
        y = tensor_on(np.concatenate([s.latents[k] for s, (_, k) in zip(series, pairs)]), self.device)

        def step(index: torch.Tensor) -> tuple[torch.Tensor, float, int]:
            index = index.to(x.device)
            states, _ = self.rnn(x[index])
            return self.trained_loss(states[:, -1], y[index])

        return lambda number: (partial(step, i) for i in torch.split(order(len(x), number), self.settings.batch_lstm))

    @classmethod
    def dummy_batch(cls, train: TrainConfig, inputs: int) -> torch.Tensor:
        return torch.zeros(train.batch_lstm, train.history, inputs)


class WindowReader(OnlineReader):
    """The last `history` samples, run through the LSTM whole at every step from a zero state, in NumPy
    (`softarm.model.cells`: a third of the torch layer's time at one window)."""

    def __init__(self, model: WindowLSTM):
        self.model = model
        self.window: deque[np.ndarray] = deque(maxlen=model.history)
        self.cell = model.cell()
        self.readout = model.readout()

    def step(self, sample: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
        self.window.append(sample)
        if len(self.window) < self.model.history:
            return None
        self.cell.reset()
        for earlier in self.window:
            state = self.cell.step(earlier)
        self.state_vector = state.astype(np.float64)
        return self.readout(state)
