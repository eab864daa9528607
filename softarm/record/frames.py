"""A block of one arm's frames as MCAP message records in one call to C (softarm/record/_frames.c), when built.

The Python encoder (RecordingWriter's messages, McapWriter.add_messages) spends about 30 µs a frame in
per-message Python; the C encoder writes the same bytes in a few. Only the float text it cannot write
exactly itself (stretch, displacement) and the active lists come from orjson, one call per block.
Without a C compiler at install time `native` is None and the Python encoder runs alone.
"""

from typing import Optional

import numpy as np
import orjson

from softarm.record.raw_image import RawImageEncoder

try:
    from softarm.record import _frames as native
except ImportError:  # installed without a C compiler: the Python encoder writes the same bytes
    native = None

TOPICS_PER_FRAME = 5  # /camera/image, /arm/stretch, /arm/nodes, /arm/excitation, /arm/disturbance


def encode_frames(stamps: np.ndarray, channels: tuple[int, ...], image: RawImageEncoder, images: np.ndarray,
                  stretch: np.ndarray, positions: np.ndarray, displacement: np.ndarray,
                  active: list[list[int]]) -> Optional[tuple[bytes, np.ndarray]]:
    """The records of n frames (channels in TOPICS_PER_FRAME order) and their datas' sizes (n, 5), or None
    where the C encoder is missing or a value lies outside what it writes exactly (|x| >= 1e6, not finite)."""
    if native is None:
        return None
    numbers = orjson.OPT_SERIALIZE_NUMPY
    sizes = np.empty((len(stamps), TOPICS_PER_FRAME), np.int64)
    records = native.encode(np.ascontiguousarray(stamps, np.int64), channels, image.middle, image.tail,
                            np.ascontiguousarray(images, np.uint8), orjson.dumps(stretch, option=numbers),
                            np.ascontiguousarray(positions, np.float64), positions.shape[1],
                            orjson.dumps(displacement, option=numbers), orjson.dumps(active), sizes)
    return None if records is None else (records, sizes)
