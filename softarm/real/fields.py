"""Numbers in a decoded message, named by a field path (`data`, `position`, `pose.position.x`, `data[0]`): ROS 2
messages (mcap_ros2's classes), protobuf messages and JSON objects alike; and the header stamp beside them."""

import dataclasses
import re
from typing import Any, Callable, Optional

import numpy as np

from softarm.errors import ConfigError, RecordingError

_STEP = re.compile(r"([A-Za-z_]\w*)(?:\[(\d+)\])?$")


def parse_source(text: str, option: str) -> tuple[str, str]:
    """'TOPIC:FIELD' -> (topic, field path); the field defaults to `data`."""
    topic, _, path = text.partition(":")
    path = path or "data"
    if not topic.startswith("/") or not all(_STEP.match(part) for part in path.split(".")):
        raise ConfigError(f"{option} {text!r}: give TOPIC:FIELD, e.g. /arm/stretch:data or /joint_states:position")
    return topic, path


def field_names(message: Any) -> list[str]:
    if isinstance(message, dict):
        return list(message)
    if hasattr(message, "DESCRIPTOR"):
        return [f.name for f in message.DESCRIPTOR.fields]
    if dataclasses.is_dataclass(message):  # rosbags' message classes (a bag's messages)
        return [f.name for f in dataclasses.fields(message) if not f.name.startswith("__")]
    return list(getattr(message, "__slots__", ()))


def _get(message: Any, name: str) -> Any:
    if isinstance(message, dict):
        return message[name]
    if name not in field_names(message):
        raise KeyError(name)
    return getattr(message, name)


def field_values(message: Any, path: str, where: str) -> np.ndarray:
    """(F,) float64 of the number or numeric array at `path`; `where` names the source in the one-line refusal."""
    value = message
    try:
        for part in path.split("."):
            name, index = _STEP.match(part).groups()
            value = _get(value, name)
            if index is not None:
                value = value[int(index)]
        array = np.atleast_1d(np.asarray(value, dtype=np.float64))
    except (KeyError, IndexError, AttributeError):
        raise RecordingError(f"{where}: the message has no field {path!r}; its fields are "
                             f"{', '.join(numeric_fields(message)) or 'none numeric'}") from None
    except (TypeError, ValueError):
        raise RecordingError(f"{where}: field {path!r} is not a number or an array of numbers") from None
    if array.ndim != 1:
        raise RecordingError(f"{where}: field {path!r} holds an array of shape {array.shape}, not a flat list")
    return array


def attribute_reader(path: str) -> Callable[[Any], Any]:
    """A fast reader of a path `field_values` has checked on a first message: attribute (or key) access and
    indexing, the values left as the decoder gave them (NumPy converts all messages' at once)."""
    steps = [_STEP.match(part).groups() for part in path.split(".")]

    def read(message: Any) -> Any:
        value = message
        for name, index in steps:
            value = value[name] if isinstance(value, dict) else getattr(value, name)
            if index is not None:
                value = value[int(index)]
        if isinstance(value, (bytes, bytearray)):  # uint8[] as the ROS 2 decoder gives it
            return list(value)
        return value if hasattr(value, "__len__") and not isinstance(value, str) else [value]
    return read


def numeric_fields(message: Any, prefix: str = "", depth: int = 0) -> list[str]:
    """The paths of every number or numeric array in a message (headers left out)."""
    out = []
    for name in field_names(message):
        if name == "header" or depth > 4:
            continue
        value = _get(message, name)
        if isinstance(value, (bool, str, bytes)):
            continue
        if isinstance(value, (int, float, np.number)) or (isinstance(value, (list, tuple)) and value
                                                          and all(isinstance(v, (int, float)) for v in value)) or (
                isinstance(value, np.ndarray) and value.ndim == 1 and value.size and value.dtype.kind in "iuf"):
            out.append(prefix + name)
        elif field_names(value) and not isinstance(value, (list, tuple)):
            out.extend(numeric_fields(value, f"{prefix}{name}.", depth + 1))
    return out


def header_stamp(message: Any) -> Optional[float]:
    """The acquisition time in s: a ROS header's stamp or a Foxglove message's `timestamp`; None without either."""
    try:  # the common case, a ROS 2 message with a header, by plain attribute access
        stamp = message.header.stamp
        return stamp.sec + stamp.nanosec * 1e-9
    except AttributeError:
        pass
    names = field_names(message)
    stamp = None
    if "header" in names:
        stamp = _get(message, "header")
        stamp = _get(stamp, "stamp") if "stamp" in field_names(stamp) else None
    elif "timestamp" in names:
        stamp = _get(message, "timestamp")
    if stamp is None:
        return None
    parts = field_names(stamp)
    if "sec" in parts:  # ROS 2's {sec, nanosec}; Foxglove's JSON time {sec, nsec}
        return _get(stamp, "sec") + _get(stamp, "nanosec" if "nanosec" in parts else "nsec") * 1e-9
    if "seconds" in parts:
        return _get(stamp, "seconds") + _get(stamp, "nanos") * 1e-9
    return None
