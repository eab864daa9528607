"""Reads softarm-recording/2 (and /1) MCAP files into arrays for the learning code.

Reads the file front to back with MCAP's stream reader rather than through its summary, so a file cut
short (a crash, a full disk) still gives every frame of every complete chunk; such a recording is
marked `truncated` and a warning says how many frames were recovered. Everything a user can get
wrong (missing, empty, foreign or newer file) raises `RecordingError` with a one-line message.
"""

import warnings
from pathlib import Path
from typing import Any, Iterator, Optional, Union

import numpy as np
import orjson
from mcap.records import Channel, Message, Metadata

from softarm.errors import RecordingError
from softarm.record.decode import mono8_image, node_positions, signal_values
from softarm.record.document import check_model
from softarm.record.format import (
    ACTIVATION,
    DISTURBANCE,
    EXCITATION,
    FORMAT,
    FORMAT_NAME,
    FORMAT_VERSION_NUMBER,
    IMAGE,
    IMPORTED,
    META_MODEL,
    META_RUN,
    NODES,
    STRETCH,
    TOPICS,
)
from softarm.record.imported import imported_recording
from softarm.record.recording import Recording, TruncatedRecordingWarning
from softarm.record.scan import file_records
from softarm.sensors import KINDS, declared

MCAP_MAGIC = b"\x89MCAP0\r\n"


def read_recording(path: Union[str, Path], nodes: bool = True) -> Recording:
    """Load every complete frame of a recording. nodes=False skips the node positions (the largest part)."""
    path = Path(path)
    model, run, messages, truncated = _scan(path, nodes)
    if model.get("kind") == IMPORTED:
        return imported_recording(path, model, run, messages, truncated)
    stamps = sorted(set.intersection(*(set(messages[t]) for t in _topics(nodes, model))))
    if not stamps:
        raise RecordingError(f"{path} holds no complete frame")
    height, width = model["camera"]["height"], model["camera"]["width"]
    frames = (np.stack([mono8_image(messages[IMAGE][s], path, height, width) for s in stamps]) > 127).astype(np.uint8)
    complete = run is not None and run.get("complete") == "true" and not truncated
    signals = {STRETCH: (("stretch",), (len(model["sensors"]),)), EXCITATION: (("displacement",), ()),
               ACTIVATION: (("activation",), (len(model.get("muscles", {}).get("names", ())),))}
    stretch, displacement, activation = (
        signal_values(messages[topic], stamps, *signals[topic], topic, path) if messages.get(topic) else None
        for topic in (STRETCH, EXCITATION, ACTIVATION))
    positions = node_positions(messages[NODES], stamps, len(model["nodes"]), path) if messages.get(NODES) else None
    active, touching = _disturbance(messages.get(DISTURBANCE, {}), stamps, model, path)
    sensed = {kind.name: signal_values(messages[kind.topic], stamps, (kind.field,), (len(model[kind.name]),),
                                       kind.topic, path) for kind in declared(model)}
    if truncated:
        warnings.warn(f"{path} is truncated: recovered {len(stamps)} complete frames", TruncatedRecordingWarning,
                      stacklevel=2)
    return Recording(path=path, model=model, times=np.array(stamps, np.int64) / 1e9, frames=frames, stretch=stretch,
                     displacement=displacement, positions=positions if nodes else None, complete=complete,
                     truncated=truncated, active=active, activation=activation, touching=touching, sensed=sensed)


def read_model(path: Union[str, Path]) -> dict[str, Any]:
    """Only the model document: cheap, for checking that a recording fits a checkpoint before loading it."""
    path = Path(path)
    try:
        for record in _records(path, stop_after_model=True):
            if isinstance(record, Metadata) and record.name == META_MODEL:
                return _model(record, path)
    except _Truncated:
        raise RecordingError(f"{path} is cut short before its metadata: no frame can be recovered") from None
    raise RecordingError(f"{path} is an MCAP file but not a softarm recording (no '{META_MODEL}' metadata)")


def count_frames(path: Union[str, Path]) -> int:
    """Complete frames a file holds (every topic present), read front to back: a `.part` file too."""
    channels: dict[int, str] = {}
    stamps: dict[str, set[int]] = {t: set() for t in TOPICS}
    try:
        for record in _records(Path(path)):
            if isinstance(record, Channel):
                channels[record.id] = record.topic
            elif isinstance(record, Message) and channels.get(record.channel_id) in stamps:
                stamps[channels[record.channel_id]].add(record.log_time)
    except _Truncated:
        pass
    return len(set.intersection(*stamps.values()))


def _topics(nodes: bool, model: Optional[dict[str, Any]] = None) -> tuple[str, ...]:
    """The topics every frame has: /3 adds the disturbance channel (its model lists `disturbances`)."""
    topics = TOPICS if nodes else tuple(t for t in TOPICS if t != NODES)
    topics = (*topics, DISTURBANCE) if model is not None and "disturbances" in model else topics
    topics = (*topics, *(kind.topic for kind in declared(model))) if model is not None else topics
    return (*topics, ACTIVATION) if model is not None and "muscles" in model else topics


def _scan(path: Path,
          nodes: bool) -> tuple[dict[str, Any], Optional[dict[str, str]], dict[str, dict[int, bytes]], bool]:
    wanted = (*_topics(nodes), DISTURBANCE, ACTIVATION, *(kind.topic for kind in KINDS.values()))
    model = run = None
    channels: dict[int, str] = {}
    messages: dict[str, dict[int, bytes]] = {t: {} for t in wanted}
    truncated = False
    try:
        for record in _records(path):
            if isinstance(record, Metadata):
                if record.name == META_MODEL:
                    model = _model(record, path)
                elif record.name == META_RUN:
                    run = dict(record.metadata)
            elif isinstance(record, Channel):
                channels[record.id] = record.topic
            elif isinstance(record, Message):
                topic = channels.get(record.channel_id)
                if topic in messages:
                    messages[topic][record.log_time] = record.data
    except _Truncated:
        truncated = True
    if model is None and truncated:
        raise RecordingError(f"{path} is cut short before its metadata: no frame can be recovered")
    if model is None:
        raise RecordingError(f"{path} is an MCAP file but not a softarm recording (no '{META_MODEL}' metadata)")
    needed = (STRETCH,) if model.get("kind") == IMPORTED else _topics(nodes, model)
    missing = [t for t in needed if not messages[t]]
    if missing and not truncated:
        raise RecordingError(f"{path} has no messages on {', '.join(missing)}")
    return model, run, messages, truncated


class _Truncated(Exception):
    pass


def _records(path: Path, stop_after_model: bool = False) -> Iterator[Any]:
    """MCAP records in file order, chunks opened; raises _Truncated where the file stops making sense."""
    try:
        with open(path, "rb") as f:
            head = f.read(len(MCAP_MAGIC))
            if not head:
                raise RecordingError(f"{path} is empty (0 bytes): not a recording")
            if head != MCAP_MAGIC:
                raise RecordingError(f"{path} is not an MCAP file (it does not start with the MCAP magic bytes)")
            stream = file_records(f, MCAP_MAGIC)
            while True:
                try:
                    record = next(stream)
                except StopIteration:
                    return
                except Exception as e:  # struct.error, McapError, zstd or CRC error: the bytes stop making sense here
                    raise _Truncated() from e
                yield record
                if stop_after_model and isinstance(record, Metadata) and record.name == META_MODEL:
                    return
    except FileNotFoundError:
        raise RecordingError(f"recording {path} not found") from None
    except IsADirectoryError:
        raise RecordingError(f"{path} is a folder, not a recording") from None
    except PermissionError:
        raise RecordingError(f"recording {path} cannot be read (permission denied)") from None


def _model(record: Metadata, path: Path) -> dict[str, Any]:
    fmt = record.metadata.get("format", "")
    name, _, version = fmt.partition("/")
    if name != FORMAT_NAME or not version.isdigit():
        raise RecordingError(f"{path}: unknown recording format {fmt!r}; softarm reads {FORMAT}")
    if int(version) > FORMAT_VERSION_NUMBER:
        raise RecordingError(f"{path} is written in {fmt}, newer than this softarm reads ({FORMAT}): upgrade softarm")
    try:
        model = orjson.loads(record.metadata["model"])
    except (KeyError, TypeError, orjson.JSONDecodeError):
        raise RecordingError(f"{path}: the '{META_MODEL}' metadata has no readable model document") from None
    check_model(model, path)
    if int(version) == 1:  # /1 predates the excitation kinds: its drive is the paper's, sideways
        model["excitation"] = {"kind": "product_of_sines", "direction": [1.0, 0.0], **model.get("excitation", {})}
    return model


def _disturbance(messages: dict[int, bytes], stamps: list[int], model: dict[str, Any],
                 path: Path) -> tuple[np.ndarray, Optional[np.ndarray]]:
    """(T, D) bool each of the disturbance channel: which of the model's D disturbances act at each frame, and which
    obstacles the arm touches (None where the model lists an obstacle and the messages do not say: unknown)."""
    kinds = [d.get("kind") for d in model.get("disturbances", [])]
    active, touching = np.zeros((len(stamps), len(kinds)), bool), np.zeros((len(stamps), len(kinds)), bool)
    if not messages:
        return active, None if "obstacle" in kinds else touching
    try:
        decoded = orjson.loads(b"[" + b",".join(messages[s] for s in stamps) + b"]")
        for k, message in enumerate(decoded):
            active[k, message["active"]] = True
            touching[k, message.get("touching", [])] = True
    except (orjson.JSONDecodeError, KeyError, TypeError, ValueError, IndexError):
        raise RecordingError(f"{path}: its {DISTURBANCE} messages do not list indices of its disturbances") from None
    if "obstacle" in kinds and not (decoded and "touching" in decoded[0]):
        return active, None
    return active, touching
