"""What every latent model is: a network from normalised input samples to a state, read by a linear head into the
normalised latent code of a frame and by an error head that predicts its own squared error; and the contract
that training, replay, evaluation and the streamer use it by.

A model is one subclass named in `registry.LATENT_MODELS`: recurrent ones (`window.WindowLSTM`,
`stream.StreamLSTM`, `stream.StreamGRU`, on `recurrent.RecurrentModel`) and a causal convolution network
(`tcn.CausalTCN`). Whatever the model, frame k is imagined from the samples up to k - lead
(`TrainConfig.lead`), and the first frame imagined is the first a `history`-sample window reaches: every
model answers for the same frames, beside the same baselines.
"""

from dataclasses import dataclass
from typing import Callable, ClassVar, Iterator, Optional, Sequence

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from softarm.config import TrainConfig
from softarm.model.cells import Readout
from softarm.model.device import device_of
from softarm.model.prediction import Prediction

StepLoss = tuple[torch.Tensor, float, int]   # (loss to minimise, loss to report, items it covers)
Step = Callable[[], StepLoss]                 # one optimisation step's forward pass
Order = Callable[[int, int], torch.Tensor]    # (items, epoch) -> that epoch's shuffle of the items


@dataclass(frozen=True)
class TrainingSeries:
    """One recording as a latent model trains on it: every frame's normalised inputs and targets, the latent
    and, where the model has a node head, the normalised node positions after it."""
    inputs: np.ndarray   # (T, P) float32
    latents: np.ndarray  # (T, K [+ A]) float32
    train_end: int       # the training segment is frames [0, train_end)
    seen: Optional[np.ndarray] = None  # (T,) bool: frames the camera has (None: all); a gap is never a target


class OnlineReader:
    """One stream read sample by sample: `step` takes a normalised sample (P,) and returns the latent answer
    (K,) and its log squared errors (K,) for the frame it lets the model imagine, or None before the first;
    `state_vector` is then the state that sample left (H,), None before the model has one."""
    state_vector: Optional[np.ndarray] = None

    def step(self, sample: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
        raise NotImplementedError


class ErrorHead(nn.Module):
    """Predicts the log of each latent feature's squared error from the model's state it reads, detached:
    learning to say how wrong it is never changes what the model predicts. Its prediction is the
    imagined frame's confidence (`Prediction.confidence`)."""

    def __init__(self, hidden: int, outputs: int):
        super().__init__()
        self.net = nn.Sequential(nn.Linear(hidden, 64), nn.ReLU(), nn.Linear(64, outputs))

    def forward(self, states: torch.Tensor) -> torch.Tensor:
        return self.net(states.detach())


class LatentModel(nn.Module):
    """A network that reads samples into a state of `train.lstm_hidden` features (`make_core`), a linear head
    to the latent and an error head; its subclass says how it reads a series, how it steps online and how an
    epoch of its training is cut. With `nodes` > 0 a third head learns the node positions from the same state
    (`train.node_target`): a training signal only, never part of an answer."""

    clip_norm: ClassVar[Optional[float]] = None  # gradient norm at most while training (None: unclipped)

    def __init__(self, inputs: int, outputs: int, train: TrainConfig, nodes: int = 0):
        super().__init__()
        self.make_core(inputs, train.lstm_hidden)
        self.head = nn.Linear(train.lstm_hidden, outputs)
        self.error = ErrorHead(train.lstm_hidden, outputs)
        self.nodes = nn.Linear(train.lstm_hidden, nodes) if nodes else None
        self.settings = train

    def make_core(self, inputs: int, width: int) -> None:
        """Build the layers from `inputs` features a sample to a state of `width` (made before the heads, so
        the seed gives every model kind its weights in the same order)."""
        raise NotImplementedError

    def trained_loss(self, states: torch.Tensor, targets: torch.Tensor) -> StepLoss:
        """The loss of the answers read from states (..., H) against targets (..., K [+ A]): the
        latent's, plus `node_target` times the node head's mean squared error where the model has one."""
        k = self.head.out_features
        loss, reported, items = latent_loss(self.head(states), self.error(states), targets[..., :k])
        if self.nodes is not None:
            loss = loss + self.settings.node_target * F.mse_loss(self.nodes(states).float(), targets[..., k:])
        return loss, reported, items

    @property
    def history(self) -> int:
        return self.settings.history

    @property
    def device(self) -> torch.device:
        """Where its weights are: what it reads goes there, what it answers comes back to the host."""
        return device_of(self)

    @property
    def lead(self) -> int:
        return self.settings.lead

    def readout(self) -> Readout:
        """Its latent and error heads in NumPy, for the online readers."""
        return Readout(self.head, self.error.net)

    @property
    def first_frame(self) -> int:
        """The first frame any model imagines: the first a `history`-sample window reaches."""
        return self.history - 1 + self.lead

    def answer(self, series: Sequence[np.ndarray]) -> list[Prediction]:
        """The answer for every frame each normalised input series (T, P) lets the model imagine."""
        raise NotImplementedError

    def answer_segments(self, series: Sequence[np.ndarray], bounds: Sequence[tuple[int, int]]) -> Prediction:
        """The answers for the frames of one segment [start, end) of each series that a window inside the
        segment reaches; targets are (series, frame) pairs. A model with memory reads each series from its
        first sample, as it would online."""
        parts = []
        for n, (prediction, (start, end)) in enumerate(zip(self.answer(series), bounds)):
            p = prediction.take((prediction.targets >= start + self.first_frame) & (prediction.targets < end))
            parts.append(Prediction(np.stack([np.full(len(p.targets), n), p.targets], axis=1), p.latents, p.log_error))
        return Prediction.join(parts)

    def online(self) -> OnlineReader:
        raise NotImplementedError

    def latents_at(self, series: torch.Tensor, samples: torch.Tensor) -> torch.Tensor:
        """(M, K) the latent answers read after `samples` (M,) of one normalised series (T, P), with gradients:
        what adaptation fine-tunes."""
        raise NotImplementedError

    def states(self, series: np.ndarray) -> np.ndarray:
        """(T, H) float64: the state the answer after each sample of a normalised series (T, P) reads;
        NaN where the model has none yet. The surprise's memory check (`softarm.trust.memory_check`) and adaptation
        (`softarm.learn.finetune`) read it."""
        raise NotImplementedError

    @classmethod
    def steps_per_epoch(cls, train_ends: Sequence[int], train: TrainConfig,
                        seen: Sequence[Optional[np.ndarray]] = ()) -> int:
        """Optimisation steps of one epoch over recordings whose training segments end at `train_ends` (`seen`:
        each recording's camera frames, None for all, where a camera has gaps)."""
        raise NotImplementedError

    def epoch(self, series: Sequence[TrainingSeries], order: Order) -> Callable[[int], Iterator[Step]]:
        """The steps of each epoch (by number) over the training segments of `series`."""
        raise NotImplementedError

    @classmethod
    def dummy_batch(cls, train: TrainConfig, inputs: int) -> torch.Tensor:
        """A batch of the real training shape, for timing a step (`softarm.learn.budget`)."""
        raise NotImplementedError


def latent_loss(mean: torch.Tensor, log_error: torch.Tensor, target: torch.Tensor) -> StepLoss:
    """Mean squared error of the latent, plus the Gaussian negative log-likelihood that teaches the error head
    its own squared error (it reads detached states, so this term leaves the prediction alone). Computed in fp32
    whatever precision the forward pass ran in."""
    mean, log_error = mean.float(), log_error.float()
    mse = F.mse_loss(mean, target)
    error = (mean.detach() - target).square()
    return mse + (log_error + error * torch.exp(-log_error)).mean(), mse.item(), len(target)

