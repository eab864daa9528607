"""Training data of a stream model: stretches of recording read side by side, in chunks.

Truncated back-propagation through time: each stretch is read from its first sample in chunks of
`sequence` samples; the state carries from chunk to chunk (so the model learns to use what it
remembers), while gradients stop at the chunk's start (so a step costs one chunk). A recording's
training segment starts a stretch of its own, from the stream's start, as replay reads it. With fewer
recordings than `streams`, each segment is cut into pieces read side by side; a piece that starts
mid-recording first reads one chunk of the samples before it, unscored, so its state has warmed up
before its answers count.
"""

import math
from dataclasses import dataclass
from typing import Iterator, Sequence

import numpy as np
import torch

from softarm.model.device import tensor_on
from softarm.model.latent import TrainingSeries


@dataclass(frozen=True)
class Piece:
    recording: int
    start: int    # first sample read
    scored: int   # first sample whose answer counts
    end: int      # one past the last sample read; sample k answers for frame k + lead


@dataclass(frozen=True)
class Group:
    """Pieces read side by side: normalised samples, normalised target latents and the scored mask."""
    samples: torch.Tensor   # (G, L, P)
    targets: torch.Tensor   # (G, L, K)
    scored: torch.Tensor    # (G, L) bool

    def chunks(self, sequence: int) -> Iterator[tuple[torch.Tensor, torch.Tensor, torch.Tensor]]:
        for first in range(0, self.samples.shape[1], sequence):
            part = slice(first, first + sequence)
            yield self.samples[:, part], self.targets[:, part], self.scored[:, part]


def pieces(train_ends: Sequence[int], streams: int, warmup: int, lead: int) -> list[Piece]:
    """Every recording's training segment, cut into equal pieces so that at least `streams` are read, none
    shorter than its warm-up (a short recording gives fewer)."""
    segments = [(n, end - lead) for n, end in enumerate(train_ends) if end - lead > 0]
    cuts = math.ceil(streams / max(1, len(segments)))
    out = []
    for n, end in segments:
        bounds = np.linspace(0, end, max(1, min(cuts, end // warmup)) + 1).round().astype(int)
        out.extend(Piece(n, max(0, a - warmup), a, b) for a, b in zip(bounds[:-1], bounds[1:]))
    return out


def partition(train_ends: Sequence[int], streams: int, warmup: int, lead: int) -> list[list[Piece]]:
    """The pieces in groups of about `streams` (as even as they go)."""
    every = pieces(train_ends, streams, warmup, lead)
    return [[every[i] for i in part] for part in np.array_split(np.arange(len(every)), math.ceil(len(every) / streams))]


def scored_chunks(part: list[Piece], sequence: int) -> int:
    """Chunks of a group with an answer that counts: its optimisation steps (warm-up-only chunks are read
    without one)."""
    length = max(p.end - p.start for p in part)
    return sum(any(p.scored - p.start < first + sequence and first < p.end - p.start for p in part)
               for first in range(0, length, sequence))


def steps_per_epoch(train_ends: Sequence[int], streams: int, sequence: int, warmup: int, lead: int) -> int:
    return sum(scored_chunks(part, sequence) for part in partition(train_ends, streams, warmup, lead))


def groups(series: Sequence[TrainingSeries], streams: int, warmup: int, lead: int, device: torch.device) -> list[Group]:
    """Every group, padded to its longest piece, its tensors on `device`."""
    ends = [s.train_end for s in series]
    return [_group(series, part, lead, device) for part in partition(ends, streams, warmup, lead)]


def _group(series: Sequence[TrainingSeries], part: list[Piece], lead: int, device: torch.device) -> Group:
    length = max(p.end - p.start for p in part)
    first = series[part[0].recording]
    samples = np.zeros((len(part), length, first.inputs.shape[1]), np.float32)
    targets = np.zeros((len(part), length, first.latents.shape[1]), np.float32)
    scored = np.zeros((len(part), length), bool)
    for g, p in enumerate(part):
        s, size = series[p.recording], p.end - p.start
        samples[g, :size] = s.inputs[p.start:p.end]
        targets[g, :size] = s.latents[p.start + lead:p.end + lead]
        scored[g, p.scored - p.start:size] = True
        if s.seen is not None:  # a camera's gap is no target
            scored[g, :size] &= s.seen[p.start + lead:p.end + lead]
    return Group(*(tensor_on(a, device) for a in (samples, targets, scored)))
