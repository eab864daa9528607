"""A block of one arm's frames as MCAP message records in one call to C (softarm/record/_frames.c), when built.

With it a frame of one arm is encoded, compressed and written in about 19 µs, against 33 µs through the Python
encoder (RecordingWriter's messages, McapWriter.add_messages): the same bytes (bench/recording.py). Only the
float text it cannot write exactly itself (stretch, displacement) and the active and touching lists come from
orjson, one call per block.
Without a C compiler at install time `native` is None and the Python encoder runs alone.
"""

from typing import Optional

import numpy as np
import orjson

from softarm.record.format import DISTURBANCE, EXCITATION, IMAGE, NODES, STRETCH
from softarm.record.raw_image import RawImageEncoder

try:
    from softarm.record import _frames as native
except ImportError:  # installed without a C compiler: the Python encoder writes the same bytes
    native = None

FRAME_TOPICS = (IMAGE, STRETCH, NODES, EXCITATION, DISTURBANCE)  # a frame's messages, in this order


def encode_frames(stamps: np.ndarray, channels: tuple[int, ...], image: RawImageEncoder, images: np.ndarray,
                  stretch: np.ndarray, positions: np.ndarray, displacement: np.ndarray,
                  active: list[list[int]],
                  touching: Optional[list[list[int]]] = None) -> Optional[tuple[bytes, np.ndarray]]:
    """The records of n frames (channels in FRAME_TOPICS order) and their datas' sizes (n, 5), or None
    where the C encoder is missing or a value lies outside what it writes exactly (|x| >= 1e6, not finite).
    `touching` (the obstacles touched at each frame) goes into /arm/disturbance where given."""
    if native is None:
        return None
    numbers = orjson.OPT_SERIALIZE_NUMPY
    sizes = np.empty((len(stamps), len(FRAME_TOPICS)), np.int64)
    records = native.encode(np.ascontiguousarray(stamps, np.int64), channels, image.middle, image.tail,
                            np.ascontiguousarray(images, np.uint8), orjson.dumps(stretch, option=numbers),
                            np.ascontiguousarray(positions, np.float64), positions.shape[1],
                            orjson.dumps(displacement, option=numbers), orjson.dumps(active),
                            b"" if touching is None else orjson.dumps(touching), sizes)
    return None if records is None else (records, sizes)
