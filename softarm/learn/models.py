"""The two networks: a stacked convolutional autoencoder for frames and an LSTM from stretch to latent.

Encoder (5 hidden layers, then the code): three stride-2 convolutions 84x52 -> 42x26 -> 21x13 -> 11x7
(8, 16, 32 channels), one stride-1 convolution, one fully connected layer of 256, then a linear
layer to the latent code. Decoder (5 hidden layers, then the image): two fully connected layers back to 32x11x7, a stride-1
convolution, two transposed convolutions 11x7 -> 22x14 -> 44x28, then a transposed convolution to
one channel of logits at 88x56, cropped to 84x52. Binary cross-entropy on the logits trains it (the
sigmoid is in the loss). Batch normalisation after every convolution gets it off the "predict the mean frame"
plateau within one epoch. The channels are few and no full-resolution layer is hidden on purpose: the whole training must fit
minutes on 2 CPU cores, and replay must decode whole recordings quickly (README has the timings).
"""

from typing import Optional

import torch
from torch import nn


def conv(c_in: int, c_out: int, stride: int) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(c_in, c_out, 3, stride=stride, padding=1), nn.BatchNorm2d(c_out), nn.ReLU())


def up(c_in: int, c_out: int) -> nn.Sequential:
    return nn.Sequential(nn.ConvTranspose2d(c_in, c_out, 4, stride=2, padding=1), nn.BatchNorm2d(c_out), nn.ReLU())


class Autoencoder(nn.Module):
    def __init__(self, height: int, width: int, latent: int):
        super().__init__()
        self.height, self.width = height, width
        self.grid = ((height + 7) // 8, (width + 7) // 8)  # size after three stride-2 convolutions
        cells = 32 * self.grid[0] * self.grid[1]
        self.encoder = nn.Sequential(
            conv(1, 8, 2), conv(8, 16, 2), conv(16, 32, 2), conv(32, 32, 1),
            nn.Flatten(), nn.Linear(cells, 256), nn.ReLU(),
            nn.Linear(256, latent))
        self.decoder = nn.Sequential(
            nn.Linear(latent, 256), nn.ReLU(),
            nn.Linear(256, cells), nn.ReLU(), nn.Unflatten(1, (32, *self.grid)),
            conv(32, 32, 1), up(32, 32), up(32, 16),
            nn.ConvTranspose2d(16, 1, 4, stride=2, padding=1))

    def encode(self, frames: torch.Tensor) -> torch.Tensor:
        """(B, H, W) frames in {0, 1} -> (B, latent) codes."""
        return self.encoder(frames.unsqueeze(1).float())

    def decode(self, codes: torch.Tensor) -> torch.Tensor:
        """(B, latent) codes -> (B, H, W) logits (apply a sigmoid for pixel probabilities)."""
        return self.decoder(codes)[:, 0, :self.height, :self.width]

    def forward(self, frames: torch.Tensor) -> torch.Tensor:
        return self.decode(self.encode(frames))


class ErrorHead(nn.Module):
    """Predicts the log of each latent feature's squared error from the recurrent state it reads, detached:
    learning to say how wrong it is never changes what the model predicts. Its prediction is the
    imagined frame's confidence (softarm.learn.imaginer.Prediction.confidence)."""

    def __init__(self, hidden: int, outputs: int):
        super().__init__()
        self.net = nn.Sequential(nn.Linear(hidden, 64), nn.ReLU(), nn.Linear(64, outputs))

    def forward(self, states: torch.Tensor) -> torch.Tensor:
        return self.net(states.detach())


class RecurrentLatent(nn.Module):
    """What both latent models are made of: one LSTM layer, a linear head to the latent and an error head."""

    def __init__(self, sensors: int, hidden: int, outputs: int):
        super().__init__()
        self.lstm = nn.LSTM(sensors, hidden, num_layers=1, batch_first=True)
        self.head = nn.Linear(hidden, outputs)
        self.error = ErrorHead(hidden, outputs)


class StretchToLatent(RecurrentLatent):
    """The paper's model: the LSTM over a window of normalised stretch samples, started afresh for every
    window; its last state predicts the latent."""

    def forward(self, windows: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, history, sensors) -> predicted latents (B, outputs) and their log squared errors (B, outputs)."""
        states, _ = self.lstm(windows)
        last = states[:, -1]
        return self.head(last), self.error(last)


State = tuple[torch.Tensor, torch.Tensor]


class StreamToLatent(RecurrentLatent):
    """The arm's memory: the LSTM reads the stream sample by sample and carries its state from the first
    sample on, so a motion seen seconds ago still shapes today's answer. Every sample's state predicts a
    latent."""

    def forward(self, samples: torch.Tensor, state: Optional[State] = None
                ) -> tuple[torch.Tensor, torch.Tensor, State]:
        """(B, T, sensors) samples, from `state` (None: the stream's start) -> latents (B, T, outputs),
        their log squared errors (B, T, outputs) and the state after the last sample."""
        states, state = self.lstm(samples, state)
        return self.head(states), self.error(states), state


def latent_model(kind: str, sensors: int, hidden: int, outputs: int) -> nn.Module:
    """The network `train.model` names."""
    return {"window": StretchToLatent, "stream": StreamToLatent}[kind](sensors, hidden, outputs)
