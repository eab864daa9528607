"""An MCAP file being written: `.part` until closed, zstd chunks, channels with embedded schemas.

Shared by the recorder and the imagination writer, so both follow the same rules: a path without
`.part` is always a closed file; `discard()` leaves nothing behind.
"""

from pathlib import Path
from typing import Sequence

import numpy as np
from foxglove_schemas_protobuf.RawImage_pb2 import RawImage
from mcap_protobuf.schema import build_file_descriptor_set

from softarm import __version__
from softarm.files import part_path, publish
from softarm.record.mcap_writer import McapWriter
from softarm.record.raw_image import RawImageEncoder


class McapFile:
    """One MCAP file being written: channels registered up front, messages added in blocks, closed or discarded."""

    def __init__(self, path: Path, image_topics: tuple[str, ...], json_schemas: dict[str, tuple[str, bytes]]):
        self.path = Path(path)
        self.part = part_path(self.path)
        self._file = open(self.part, "wb")
        self.writer = McapWriter(self._file)
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
        self._images: dict[tuple[int, int], RawImageEncoder] = {}

    def add_frames(self, stamps: Sequence[int], messages: dict[str, Sequence[bytes]]) -> None:
        """One message per frame on each topic, frame by frame in the order of `messages`; log time = publish
        time = the frame's stamp (ns)."""
        channels = [self.channels[topic] for topic in messages]
        if any(len(m) != len(stamps) for m in messages.values()):
            raise ValueError(f"one message per frame on every topic: {len(stamps)} frames, "
                             f"{[len(m) for m in messages.values()]} messages")
        self.writer.add_messages(channels * len(stamps), np.repeat(stamps, len(channels)).tolist(),
                                 [data for frame in zip(*messages.values()) for data in frame])

    def add_records(self, stamps: np.ndarray, topics: Sequence[str], records: bytes, sizes: np.ndarray) -> None:
        """Frames already encoded as message records (McapWriter.add_records), one per topic per frame in the
        order of `topics`; `sizes` (frames, topics) the datas' lengths."""
        channels = np.array([self.channels[topic] for topic in topics], np.int64)
        self.writer.add_records(np.tile(channels, len(stamps)), np.repeat(stamps, len(topics)), records,
                                sizes.reshape(-1))

    def image_encoder(self, height: int, width: int) -> RawImageEncoder:
        """The encoder of mono8 foxglove.RawImage messages of this size, frame id "camera"."""
        return self._images.setdefault((height, width), RawImageEncoder(height, width, "camera"))

    def images(self, pixels: np.ndarray, stamps: Sequence[int]) -> list[bytes]:
        """mono8 foxglove.RawImage messages of (n, height, width) bytes, frame id "camera"."""
        n, height, width = pixels.shape
        return self.image_encoder(height, width).encode(pixels.reshape(n, -1), stamps)

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
