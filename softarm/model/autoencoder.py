"""The frame autoencoder: a stacked convolutional encoder to a small latent code and a decoder back to pixels.

Encoder (5 hidden layers, then the code): three stride-2 convolutions 84x52 -> 42x26 -> 21x13 -> 11x7
(8, 16, 32 channels), one stride-1 convolution, one fully connected layer of 256, then a linear
layer to the latent code. Decoder (5 hidden layers, then the image): two fully connected layers back to
32x11x7, a stride-1 convolution, two transposed convolutions 11x7 -> 22x14 -> 44x28, then a transposed
convolution to one channel of logits at 88x56, cropped to 84x52. Binary cross-entropy on the logits trains
it (the sigmoid is in the loss). Batch normalisation after every convolution gets it off the "predict the
mean frame" plateau within one epoch. The channels are few and no full-resolution layer is hidden on
purpose: the whole training must fit minutes on 2 CPU cores, and replay must decode whole recordings
quickly (README has the timings).
"""

from typing import Any, Callable, Protocol, Union

import numpy as np
import torch
from torch import nn

from softarm.model.device import array_of, device_of, tensor_on

BATCH = 256  # frames or codes per pass of inference: the fastest batch on a 2-core CPU


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


def in_batches(function: Callable[[Any], Any], items: Union[torch.Tensor, "Frames"]) -> Any:
    """`function` over `items` (a tensor, or frames that slice into arrays) BATCH at a time, its answers (a tensor,
    or a tuple of them) joined: the one inference loop of the model room."""
    answers = [function(items[i:i + BATCH]) for i in range(0, len(items), BATCH)]
    if isinstance(answers[0], tuple):
        return tuple(torch.cat(parts) for parts in zip(*answers))
    return torch.cat(answers)


class Frames(Protocol):
    """Frames (M, H, W) an array gives, or anything that slices into such arrays (a training's packed frames)."""
    def __len__(self) -> int: ...
    def __getitem__(self, key: slice) -> np.ndarray: ...


@torch.inference_mode()
def encode_frames(autoencoder: Autoencoder, frames: Frames) -> np.ndarray:
    """Raw latent codes (M, F) of frames (M, H, W), BATCH at a time, on the autoencoder's device."""
    device = device_of(autoencoder)
    return array_of(in_batches(lambda batch: autoencoder.encode(tensor_on(batch, device)), frames))


@torch.inference_mode()
def decode_codes(autoencoder: Autoencoder, codes: np.ndarray) -> np.ndarray:
    """Pixel probabilities (M, H, W) of raw latent codes (M, F)."""
    z = tensor_on(codes.astype(np.float32), device_of(autoencoder))
    return array_of(in_batches(lambda batch: torch.sigmoid(autoencoder.decode(batch)), z))


@torch.inference_mode()
def reconstruct(autoencoder: Autoencoder, frames: np.ndarray) -> np.ndarray:
    """Pixel probabilities (M, H, W) of the autoencoder's own reconstruction of frames (M, H, W)."""
    x = tensor_on(frames, device_of(autoencoder))
    return array_of(in_batches(lambda batch: torch.sigmoid(autoencoder(batch)), x))
