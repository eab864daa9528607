"""The causal convolution network's training data: rows of ROW scored samples, each after the RECEPTIVE - 1
samples that shape its first state.

With that context every scored state sees exactly what it sees when the whole series is read (`CausalTCN.answer`):
a row that starts within a receptive field of the recording's start begins at its first sample, as the series
does, and is padded at its end instead. A step reads as many scored samples as a stream model's
(`streams` x `sequence`), in longer rows: the context is then a smaller share of the arithmetic.
"""

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
import torch

from softarm.config import TrainConfig
from softarm.model.device import tensor_on
from softarm.model.latent import TrainingSeries

ROW = 400  # scored samples a row: 4 s


@dataclass(frozen=True)
class Rows:
    samples: torch.Tensor   # (N, context + ROW, P)
    targets: torch.Tensor   # (N, context + ROW, K): the latent of the frame each sample answers for
    scored: torch.Tensor    # (N, context + ROW) bool


def per_step(train: TrainConfig) -> int:
    """Rows a step reads."""
    return max(1, math.ceil(train.streams * train.sequence / ROW))


def starts(train_ends: Sequence[int], seen: Sequence[Optional[np.ndarray]], lead: int) -> list[tuple[int, int]]:
    """(recording, first scored sample) of every row with something to score: sample k answers frame k + lead,
    inside the training segment and seen by the camera."""
    masks = list(seen) or [None] * len(train_ends)
    out = []
    for n, (end, mask) in enumerate(zip(train_ends, masks)):
        for first in range(0, max(0, end - lead), ROW):
            if mask is None or mask[first + lead:min(first + ROW, end - lead) + lead].any():
                out.append((n, first))
    return out


def row_steps(train_ends: Sequence[int], seen: Sequence[Optional[np.ndarray]], train: TrainConfig) -> int:
    return math.ceil(len(starts(train_ends, seen, train.lead)) / per_step(train))


def cut(series: Sequence[TrainingSeries], train: TrainConfig, receptive: int, device: torch.device) -> Rows:
    """Every row of the training segments, left-aligned, its tensors on `device`."""
    lead, context = train.lead, receptive - 1
    every = starts([s.train_end for s in series], [s.seen for s in series], lead)
    width = context + ROW
    samples = np.zeros((len(every), width, series[0].inputs.shape[1]), np.float32)
    targets = np.zeros((len(every), width, series[0].latents.shape[1]), np.float32)
    scored = np.zeros((len(every), width), bool)
    for r, (n, first) in enumerate(every):
        s = series[n]
        begin, end = max(0, first - context), min(first + ROW, s.train_end - lead)
        samples[r, :end - begin] = s.inputs[begin:end]
        targets[r, :end - begin] = s.latents[begin + lead:end + lead]
        offset = first - begin
        scored[r, offset:end - begin] = True if s.seen is None else s.seen[first + lead:end + lead]
    return Rows(*(tensor_on(a, device) for a in (samples, targets, scored)))
