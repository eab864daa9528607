"""Decoding a recording's messages into arrays, every frame's at once; a message that does not decode is refused
in one line naming the file and the topic."""

from pathlib import Path

import numpy as np
import orjson
from foxglove_schemas_protobuf.RawImage_pb2 import RawImage

from softarm.errors import RecordingError
from softarm.record.format import IMAGE, NODES

try:
    from softarm.record import _nodes as native
except ImportError:  # installed without a C compiler: orjson reads the same values
    native = None


def signal_values(messages: dict[int, bytes], stamps: list[int], keys: tuple[str, ...], shape: tuple[int, ...],
                  topic: str, path: Path) -> np.ndarray:
    """(T, *shape) float64: the field `keys[0]` of every frame's JSON message, decoded in one call (one array
    document: much cheaper than one call each); a message that does not decode to it is refused."""
    try:
        decoded = orjson.loads(b"[" + b",".join(messages[s] for s in stamps) + b"]")
        values = np.array([m[keys[0]] for m in decoded], np.float64)
    except (orjson.JSONDecodeError, KeyError, TypeError, ValueError, IndexError):
        values = None
    if values is None or values.shape != (len(stamps), *shape):
        raise RecordingError(f"{path}: its {topic} messages do not hold {keys[0]} of shape {shape} for every frame")
    return values


def node_positions(messages: dict[int, bytes], stamps: list[int], nodes: int, path: Path) -> np.ndarray:
    """(T, nodes, 2) float64: every frame's node positions, parsed in C where the messages are of the form softarm
    writes (ten times faster than orjson), else as `signal_values` reads any JSON."""
    if native is not None and nodes > 0:  # no nodes: orjson refuses the empty lists as it always has
        parsed = native.positions(b"\n".join(messages[s] for s in stamps), len(stamps), nodes)
        if parsed is not None:
            return np.frombuffer(parsed, np.float64).reshape(len(stamps), nodes, 2)
    return signal_values(messages, stamps, ("positions",), (nodes, 2), NODES, path)


def mono8_image(data: bytes, path: Path, height: int, width: int) -> np.ndarray:
    """The mono8 pixels (height, width) of one foxglove.RawImage message."""
    try:
        msg = RawImage.FromString(data)
    except Exception:
        raise RecordingError(f"{path}: a {IMAGE} message is not a foxglove.RawImage") from None
    if msg.encoding != "mono8" or (msg.height, msg.width) != (height, width):
        raise RecordingError(f"{path}: images are {msg.encoding} {msg.height}x{msg.width}, but the model says "
                             f"mono8 {height}x{width}")
    if msg.step < msg.width or len(msg.data) != msg.height * msg.step:
        raise RecordingError(f"{path}: an image holds {len(msg.data)} bytes, not {msg.height} rows of {msg.step}")
    return np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.step)[:, :msg.width]
