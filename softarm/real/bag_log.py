"""A robot's ROS bag, read without ROS by `rosbags`: a ROS 1 `.bag`, or a ROS 2 bag folder (sqlite3 or MCAP storage).
The message types come from the definitions the bag carries, or, for ROS 2 bags written before they were stored
(sqlite3 bags of Humble and earlier), from rosbags' own copy of the standard ones."""

from itertools import islice
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from softarm.errors import RecordingError
from softarm.real.log import LogFile, Topic


class BagLog(LogFile):
    """A ROS 1 or ROS 2 bag: `topics` from its connections, messages decoded into rosbags' message classes (the same
    field names as the ROS 2 decoder's; arrays as NumPy arrays)."""

    def __init__(self, path: Path):
        self.path = Path(path)
        try:
            self._reader = AnyReader([self.path], default_typestore=get_typestore(Stores.LATEST))
            self._reader.open()
        except Exception as e:  # rosbags' reader errors, a damaged database or index, YAML that does not parse
            raise RecordingError(f"{self.path} is not a readable ROS bag ({type(e).__name__}: {e})") from None
        encoding = "cdr" if self._reader.is2 else "ros1"
        self._connections: dict[str, list[Any]] = {}
        for c in self._reader.connections:
            self._connections.setdefault(c.topic, []).append(c)
        self.topics = {name: Topic(name, cs[0].msgtype, encoding, sum(c.msgcount for c in cs))
                       for name, cs in self._connections.items()}

    def close(self) -> None:
        self._reader.close()

    def raw(self, *topics: str) -> Iterator[tuple[str, int, bytes, Callable[[bytes], Any]]]:
        chosen = [c for t in topics for c in self._connections.get(t, ())]
        decoders = {t: self.decoder(t) for t in topics if t in self._connections}
        if not chosen:
            return
        try:
            for connection, log_time, data in self._reader.messages(connections=chosen):
                yield connection.topic, log_time, bytes(data), decoders[connection.topic]
        except RecordingError:
            raise
        except Exception as e:  # a damaged chunk, index or database page
            raise RecordingError(f"{self.path} is damaged ({type(e).__name__}: {e})") from None

    def decoder(self, topic: str) -> Callable[[bytes], Any]:
        msgtype, reader, path = self._connections[topic][0].msgtype, self._reader, self.path

        def decode(data: bytes) -> Any:
            try:
                return reader.deserialize(data, msgtype)
            except Exception as e:  # bytes that do not match the type: a damaged message
                raise RecordingError(f"{path}: a message on {topic} does not decode ({type(e).__name__}: {e})"
                                     ) from None
        return decode

    def spread(self, topic: str, count: int) -> list[Any]:
        connections, decode, out = self._connections.get(topic, []), self.decoder(topic), []
        if not connections or count < 1:
            return out
        try:
            for start in np.linspace(self._reader.start_time, self._reader.end_time, count).astype(np.int64):
                found = next(islice(self._reader.messages(connections=connections, start=int(start)), 1), None)
                if found is not None and (not out or found[1] != out[-1][0]):
                    out.append((found[1], decode(bytes(found[2]))))
        except RecordingError:
            raise
        except Exception as e:
            raise RecordingError(f"{self.path} is damaged ({type(e).__name__}: {e})") from None
        return [message for _, message in out]

    def seconds(self) -> float:
        return self._reader.duration / 1e9 if self._reader.message_count else 0.0
