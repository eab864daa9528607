"""A robot's log as `softarm import` reads it, whatever its format: its topics, and each topic's messages decoded in
log-time order. `formats.open_log` picks the reader by the file's own bytes: MCAP (`mcap_log`), or a ROS 1 `.bag`
or a ROS 2 bag folder (`bag_log`)."""

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Optional

from softarm.real.fields import numeric_fields

IMAGE_SCHEMAS = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage", "foxglove.RawImage",
                 "foxglove.CompressedImage")


@dataclass(frozen=True)
class Topic:
    name: str
    schema: str      # e.g. sensor_msgs/msg/CompressedImage, foxglove.RawImage
    encoding: str    # the message encoding: cdr, ros1, protobuf, json, ...
    messages: int

    @property
    def image(self) -> bool:
        return self.schema in IMAGE_SCHEMAS or self.schema.replace("/msg/", "/") in IMAGE_SCHEMAS


class LogFile:
    """An open log: `topics`, `raw(topics)` undecoded with a decoder beside, `messages(topic)` decoded. A format is a
    subclass that gives `topics` and `raw`, `decoder`, `spread`, `seconds` and `close`."""

    path: Path
    topics: dict[str, Topic]

    def __enter__(self) -> "LogFile":
        return self

    def __exit__(self, *_: Any) -> None:
        self.close()

    def close(self) -> None:
        raise NotImplementedError

    def raw(self, *topics: str) -> Iterator[tuple[str, int, bytes, Callable[[bytes], Any]]]:
        """(topic, log time ns, message bytes, a decoder of them) for each message on `topics`, in log-time order."""
        raise NotImplementedError

    def decoder(self, topic: str) -> Callable[[bytes], Any]:
        """The decoder of a topic's messages (a plain function: the import's worker processes inherit it)."""
        raise NotImplementedError

    def spread(self, topic: str, count: int) -> list[Any]:
        """About `count` decoded messages of `topic` spread evenly over the log's time, read through its index."""
        raise NotImplementedError

    def seconds(self) -> float:
        """The time the log spans (0 where it does not say)."""
        raise NotImplementedError

    def messages(self, topic: str) -> Iterator[tuple[int, Any]]:
        """(log time ns, decoded message) for each message on `topic`."""
        for _, log_time, data, decode in self.raw(topic):
            yield log_time, decode(data)

    def first(self, topic: str) -> Optional[Any]:
        return next((message for _, message in self.messages(topic)), None)

    def describe(self) -> str:
        """The image topics and the numeric fields of the others, for a message that names what the log has."""
        images = [t.name for t in self.topics.values() if t.image]
        numeric = []
        for t in self.topics.values():
            if not t.image and t.messages:
                try:
                    numeric.extend(f"{t.name}:{f}" for f in numeric_fields(self.first(t.name)))
                except Exception:  # a topic no decoder reads is simply not listed
                    continue
        return (f"image topics: {', '.join(images) or 'none'}; numeric topics (TOPIC:FIELD): "
                f"{', '.join(numeric) or 'none'}")

