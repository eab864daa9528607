"""foxglove.RawImage messages encoded by hand: the same bytes as protobuf's serializer, a block at a time.

Every field but the timestamp and the pixels is the same for all frames of a camera, so the bytes
around them are built once; a frame costs two varints and a join. Field numbers and wire types are
those of foxglove's RawImage.proto (width, height and step are fixed32), written in field-number order
as protobuf writes them; a test holds the result equal to `RawImage.SerializeToString()`.
"""

import struct
from functools import lru_cache
from typing import Sequence

import numpy as np


@lru_cache(maxsize=4096)  # frame times repeat their nanoseconds every second and their seconds 100 times
def varint(value: int) -> bytes:
    out = bytearray()
    while True:
        byte = value & 0x7F
        value >>= 7
        if value:
            out.append(byte | 0x80)
        else:
            out.append(byte)
            return bytes(out)


def field(tag: int, payload: bytes) -> bytes:
    """A length-delimited field (wire type 2)."""
    return bytes([tag]) + varint(len(payload)) + payload


class RawImageEncoder:
    """mono8 images of one size and frame id; `encode` takes (n, height * width) pixels and n times in ns."""

    def __init__(self, height: int, width: int, frame_id: str, encoding: str = "mono8"):
        # the bytes between the timestamp and the pixels, and after the pixels (also the C encoder's, _frames.c)
        self.middle = (struct.pack("<BIBI", 0x15, width, 0x1D, height) + field(0x22, encoding.encode())
                        + struct.pack("<BI", 0x2D, width) + bytes([0x32]) + varint(height * width))
        self.tail = field(0x3A, frame_id.encode()) if frame_id else b""

    def encode(self, pixels: np.ndarray, stamps: Sequence[int]) -> list[bytes]:
        middle, tail = self.middle, self.tail
        return [field(0x0A, timestamp(ns)) + middle + row.tobytes() + tail for row, ns in zip(pixels, stamps)]


def timestamp(ns: int) -> bytes:
    """google.protobuf.Timestamp {seconds, nanos}; zero fields are left out, as proto3 does."""
    seconds, nanos = divmod(ns, 1_000_000_000)
    return (b"\x08" + varint(seconds) if seconds else b"") + (b"\x10" + varint(nanos) if nanos else b"")
