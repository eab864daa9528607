"""A training's frames kept eight pixels to a byte, in memory.

Frames are binary (0/1), and a training reads them many times: the autoencoder's batches, the codes, the scores.
Packed along each row (`np.packbits`), a corpus of 384 000 frames of 84 x 52 takes 210 MB instead of 1.7 GB, so
it stays in memory: no copy goes to disk on the way (the memory-mapped cache of earlier releases wrote 3.4 GB a
corpus training, 10-22 s of a refit in two profiles), and resident memory grows by 546 bytes a frame. Indexing
unpacks only the frames it returns, as uint8 0/1 arrays equal to indexing the unpacked frames.
"""

from typing import Any, Sequence

import numpy as np
import torch

CHUNK = 4096  # frames unpacked at a time where all of them are summed


class PackedFrames:
    def __init__(self, bits: np.ndarray, width: int):
        self.bits = bits    # (T, H, ceil(W / 8)) uint8: each row's pixels, eight to a byte, first pixel highest
        self.width = width  # W: pixels a row unpacks to

    @classmethod
    def pack(cls, frames: np.ndarray) -> "PackedFrames":
        """Binary frames (T, H, W) packed; anything but 0 and 1 would not survive packing, so it is refused."""
        if frames.dtype != np.uint8 or frames.ndim != 3 or (frames.size and frames.max() > 1):
            raise ValueError("only binary uint8 frames (T, H, W) of 0 and 1 pack")
        return cls(np.packbits(frames, axis=-1), frames.shape[-1])

    @classmethod
    def join(cls, parts: Sequence["PackedFrames"]) -> "PackedFrames":
        """The parts' frames one after another."""
        widths = {p.width for p in parts}
        if len(widths) != 1:
            raise ValueError("frames of different widths do not join")
        return cls(np.concatenate([p.bits for p in parts]), widths.pop())

    def __len__(self) -> int:
        return len(self.bits)

    @property
    def shape(self) -> tuple[int, int, int]:
        return (len(self.bits), self.bits.shape[1], self.width)

    def __getitem__(self, key: Any) -> np.ndarray:
        """The frames `key` picks (an index, a slice, an index or mask array), unpacked: uint8 0/1."""
        return np.unpackbits(self.bits[key], axis=-1, count=self.width)

    def select(self, key: Any) -> "PackedFrames":
        """The frames `key` picks (a slice or an index or mask array), still packed."""
        return PackedFrames(self.bits[key], self.width)

    def on(self, device: torch.device) -> "DeviceFrames":
        """The same frames as one packed tensor on `device`, unpacked there a batch at a time: a training's
        batches never cross from the host (on the CPU the tensor is this array's own memory)."""
        return DeviceFrames(torch.from_numpy(self.bits).to(device), self.width)

    def mean(self) -> np.ndarray:
        """(H, W) float64: the mean frame, as `np.mean(frames, axis=0)` of the unpacked frames gives it (the sums
        are integer counts, exact in any order)."""
        total = np.zeros(self.shape[1:], np.int64)
        for start in range(0, len(self), CHUNK):
            total += self[start:start + CHUNK].sum(axis=0, dtype=np.int64)
        return total / len(self)


class DeviceFrames:
    """Packed frames on a torch device: `frames[index]` is the (N, H, W) uint8 0/1 tensor of the frames an index
    tensor picks, unpacked on the device with the bit order of `np.unpackbits` (first pixel highest)."""

    def __init__(self, bits: torch.Tensor, width: int):
        self.bits = bits
        self.width = width
        self.shifts = torch.arange(7, -1, -1, dtype=torch.uint8, device=bits.device)

    def __len__(self) -> int:
        return len(self.bits)

    def __getitem__(self, index: torch.Tensor) -> torch.Tensor:
        picked = self.bits[index]
        return ((picked.unsqueeze(-1) >> self.shifts) & 1).flatten(-2)[..., :self.width]
