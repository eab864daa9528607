"""Blocks of frames shared between the simulating process and its writer processes, without copies.

Each slot holds one block for every arm (camera frames, stretch, node positions, drive displacement)
in an anonymous shared mapping made before the writers fork, so a block is written once by the
simulation and read in place by the writers. Two slots let the simulation fill one while the
writers encode the other.
"""

import mmap
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class BlockShape:
    arms: int
    frames: int     # frames per block, at most
    height: int
    width: int
    sensors: int
    nodes: int

    def fields(self) -> dict[str, tuple[tuple[int, ...], str]]:
        a, b = self.arms, self.frames
        return {"images": ((a, b, self.height, self.width), "uint8"), "stretch": ((a, b, self.sensors), "float64"),
                "positions": ((a, b, self.nodes, 2), "float64"), "displacement": ((a, b), "float64")}

    @property
    def bytes(self) -> int:
        """Bytes of one slot."""
        return sum(int(np.prod(shape)) * np.dtype(dtype).itemsize for shape, dtype in self.fields().values())


class Slot:
    """One block's arrays over one shared mapping: the parent writes them, the writers read them."""

    def __init__(self, shape: BlockShape):
        self._memory = mmap.mmap(-1, max(shape.bytes, 1))  # anonymous and shared: forked children see the same pages
        self.arrays: dict[str, np.ndarray] = {}
        offset = 0
        for name, (dims, dtype) in shape.fields().items():
            array = np.ndarray(dims, dtype, buffer=self._memory, offset=offset)
            self.arrays[name] = array
            offset += array.nbytes

    def put(self, images: np.ndarray, stretch: np.ndarray, positions: np.ndarray, displacement: np.ndarray) -> int:
        """Copy a block of every arm in; returns its frame count."""
        n = images.shape[1]
        for name, values in (("images", images), ("stretch", stretch), ("positions", positions),
                             ("displacement", displacement)):
            self.arrays[name][:, :n] = values
        return n

    def arm(self, arm: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The first n frames of one arm: views, valid until the slot is filled again."""
        a = self.arrays
        return a["images"][arm, :n], a["stretch"][arm, :n], a["positions"][arm, :n], a["displacement"][arm, :n]

    def release(self) -> None:
        """Unmap the block (its arrays must not be used after this)."""
        self.arrays.clear()
        try:
            self._memory.close()
        except BufferError:  # a view still exists somewhere: the mapping goes when it does
            pass
