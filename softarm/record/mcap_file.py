"""An MCAP file being written: `.part` until closed, zstd chunks, channels with embedded schemas.

Shared by the recorder and the imagination writer, so both follow the same rules: a path without
`.part` is always a closed file; `discard()` leaves nothing behind.
"""

from pathlib import Path

from foxglove_schemas_protobuf.RawImage_pb2 import RawImage
from mcap.writer import CompressionType, Writer
from mcap_protobuf.schema import build_file_descriptor_set

from softarm import __version__
from softarm.files import part_path, publish


class McapFile:
    """One MCAP file being written: channels registered up front, messages added, closed or discarded."""

    def __init__(self, path: Path, image_topics: tuple[str, ...], json_schemas: dict[str, tuple[str, bytes]]):
        self.path = Path(path)
        self.part = part_path(self.path)
        self._file = open(self.part, "wb")
        self.writer = Writer(self._file, compression=CompressionType.ZSTD)
        self.writer.start(profile="", library=f"softarm/{__version__}")
        self.channels: dict[str, int] = {}
        if image_topics:
            image_schema = self.writer.register_schema(
                "foxglove.RawImage", "protobuf", build_file_descriptor_set(RawImage).SerializeToString())
            for topic in image_topics:
                self.channels[topic] = self.writer.register_channel(topic, "protobuf", image_schema)
        for topic, (name, schema) in json_schemas.items():
            schema_id = self.writer.register_schema(name, "jsonschema", schema)
            self.channels[topic] = self.writer.register_channel(topic, "json", schema_id)
        self._image = RawImage(encoding="mono8")

    def add(self, topic: str, ns: int, data: bytes) -> None:
        """One message; log time = publish time = ns."""
        self.writer.add_message(self.channels[topic], ns, data, ns)

    def add_image(self, topic: str, ns: int, pixels: bytes, height: int, width: int, frame_id: str) -> None:
        """A mono8 foxglove.RawImage, rows of `width` bytes."""
        image = self._image
        image.timestamp.FromNanoseconds(ns)
        image.frame_id, image.width, image.height, image.step, image.data = frame_id, width, height, width, pixels
        self.add(topic, ns, image.SerializeToString())

    def close(self, metadata: dict[str, dict[str, str]]) -> Path:
        """Add the closing metadata records, write summary and index, rename to the final path."""
        for name, values in metadata.items():
            self.writer.add_metadata(name, values)
        self.writer.finish()
        self._file.close()
        return publish(self.path)

    def discard(self) -> None:
        self._file.close()
        self.part.unlink(missing_ok=True)
