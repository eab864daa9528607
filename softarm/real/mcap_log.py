"""A robot's MCAP log (ROS 2 or Foxglove), read without ROS: its topics from the summary, and their messages decoded by
the `mcap` packages' own ROS 2 (CDR) and protobuf decoders, one topic at a time in log-time order."""

import struct
from pathlib import Path
from typing import Any, BinaryIO, Callable, Iterator

import numpy as np
import orjson
from mcap.exceptions import McapError
from mcap.reader import McapReader, make_reader
from mcap.records import Channel, Message, Schema
from mcap_protobuf.decoder import DecoderFactory as ProtobufDecoders
from mcap_ros2.decoder import DecoderFactory as Ros2Decoders

from softarm.errors import RecordingError
from softarm.real.log import LogFile, Topic
from softarm.record.reader import MCAP_MAGIC
from softarm.record.scan import file_records


class McapLog(LogFile):
    """An MCAP log: `topics` from its summary, messages decoded by the `mcap` packages' ROS 2 (CDR) and protobuf
    decoders, or JSON."""

    def __init__(self, path: Path):
        self.path = Path(path)
        try:
            self._file: BinaryIO = open(self.path, "rb")
        except FileNotFoundError:
            raise RecordingError(f"log {self.path} not found") from None
        except IsADirectoryError:
            raise RecordingError(f"{self.path} is a folder, not a log") from None
        try:
            self._reader: McapReader = make_reader(self._file)
            summary = self._reader.get_summary()
        except (McapError, ValueError, EOFError, OSError, struct.error) as e:
            self.close()
            raise RecordingError(f"{self.path} is not a readable MCAP log ({type(e).__name__}: {e}); a log cut short "
                                 "has no summary: run `mcap recover` on it first") from None
        if summary is None:
            self.close()
            raise RecordingError(f"{self.path} has no summary section; run `mcap recover` on it first")
        self._factories = (Ros2Decoders(), ProtobufDecoders())
        counts = summary.statistics.channel_message_counts if summary.statistics else {}
        self._summary = summary
        self.topics = {c.topic: Topic(c.topic, summary.schemas[c.schema_id].name if c.schema_id else "",
                                      c.message_encoding, counts.get(c.id, 0)) for c in summary.channels.values()}

    def close(self) -> None:
        self._file.close()

    def raw(self, *topics: str) -> Iterator[tuple[str, int, bytes, Callable[[bytes], Any]]]:
        """(topic, log time ns, message bytes, a decoder of them) for each message on `topics`, in file order (a
        topic's messages in the order they were logged), read in one pass with softarm's fast record scanner."""
        schemas: dict[int, Schema] = {}
        channels: dict[int, tuple[str, Callable[[bytes], Any]]] = {}
        self._file.seek(0)
        try:
            for record in file_records(self._file, MCAP_MAGIC):
                if isinstance(record, Message):
                    if record.channel_id in channels:
                        topic, decode = channels[record.channel_id]
                        yield topic, record.log_time, record.data, decode
                elif isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel) and record.topic in topics:
                    channels[record.id] = (record.topic, self._decoder(record.message_encoding,
                                                                       schemas.get(record.schema_id), record.topic))
        except Exception as e:  # struct, MCAP, zstd, lz4 or CRC errors: the bytes stop making sense here
            raise RecordingError(f"{self.path} is damaged ({type(e).__name__}: {e})") from None

    def _decoder(self, encoding: str, schema: Any, topic: str) -> Callable[[bytes], Any]:
        """The decoder of a channel's messages; a message it cannot read becomes one line naming the topic."""
        found = orjson.loads if encoding == "json" else next(
            (d for d in (f.decoder_for(encoding, schema) for f in self._factories) if d is not None), None)
        if found is not None:
            path = self.path

            def decode(data: bytes) -> Any:
                try:
                    return found(data)
                except Exception as e:  # CDR, protobuf or JSON that does not match its schema: a damaged message
                    raise RecordingError(f"{path}: a message on {topic} does not decode ({type(e).__name__}: {e})"
                                         ) from None
            return decode
        raise RecordingError(f"{self.path}: no decoder reads {topic} (message encoding {encoding!r}, schema "
                             f"{getattr(schema, 'name', None)!r}); "
                             f"softarm reads ROS 2 (cdr), protobuf and json messages")

    def seconds(self) -> float:
        """The time the log spans, from its summary's statistics (0 where it has none)."""
        stats = self._summary.statistics
        return (stats.message_end_time - stats.message_start_time) / 1e9 if stats is not None else 0.0

    def spread(self, topic: str, count: int) -> list[Any]:
        """About `count` decoded messages of `topic` spread evenly over the log's time, read through its chunk
        index (a few chunks, not the whole file)."""
        stats = self._summary.statistics
        decode, out = self.decoder(topic), []
        if stats is None or count < 1:
            return out
        try:
            for start in np.linspace(stats.message_start_time, stats.message_end_time, count).astype(np.int64):
                found = next(self._reader.iter_messages(topics=[topic], starting_at=int(start)), None)
                if found is not None and (not out or found[2].log_time != out[-1][0]):
                    out.append((found[2].log_time, decode(found[2].data)))
        except RecordingError:
            raise
        except Exception as e:  # a damaged chunk or index
            raise RecordingError(f"{self.path} is damaged ({type(e).__name__}: {e})") from None
        return [message for _, message in out]

    def decoder(self, topic: str) -> Callable[[bytes], Any]:
        """The decoder of a topic's messages, from the log's summary (before any pass over its messages)."""
        channel = next(c for c in self._summary.channels.values() if c.topic == topic)
        return self._decoder(channel.message_encoding, self._summary.schemas.get(channel.schema_id), topic)
