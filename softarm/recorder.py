"""Writes one arm's run as a softarm-recording/1 MCAP file (RECORDING.md).

The file grows as `<name>.mcap.part` and is renamed when it is closed, so a path without `.part`
is always a whole file: closed normally (`complete = "true"`), or on Ctrl-C with every frame
recorded so far (`complete = "false"`). A failed run discards its `.part`.
"""

import os
from pathlib import Path
from typing import Any

import numpy as np
import orjson
from foxglove_schemas_protobuf.RawImage_pb2 import RawImage
from mcap.writer import CompressionType, Writer
from mcap_protobuf.schema import build_file_descriptor_set

from softarm import __version__
from softarm.body import Body
from softarm.camera import world_to_pixel
from softarm.config import Config
from softarm.excitation import Drive
from softarm.recording_format import (EXCITATION, FORMAT, IMAGE, JSON_SCHEMAS, META_MODEL, META_RUN, NODES,
                                      POSITION_DECIMALS, STRETCH)


def model_metadata(config: Config, body: Body, drive: Drive, seed: int,
                   positions: np.ndarray, velocities: np.ndarray) -> dict[str, Any]:
    """Everything another program needs to re-simulate this arm without softarm (MODEL.md)."""
    return {
        "nodes": body.rest.tolist(),
        "masses": body.masses.tolist(),
        "springs": body.springs.tolist(),
        "rest_lengths": body.rest_lengths.tolist(),
        "stiffness": body.stiffness.tolist(),
        "damping": body.damping.tolist(),
        "driven": body.driven.tolist(),
        "gravity": body.gravity.tolist(),
        "excitation": {"amplitude": drive.amplitude, "frequencies": list(drive.frequencies),
                       "time_offset": drive.time_offset},
        "sensors": body.sensors.tolist(),
        "outline": body.outline.tolist(),
        "camera": {"width": config.camera.width, "height": config.camera.height,
                   "world_to_pixel": world_to_pixel(config.camera).tolist()},
        "frame_dt": config.integration.frame_dt,
        "substeps": config.integration.substeps,
        "integrator": config.integration.integrator,
        "initial": {"positions": positions.tolist(), "velocities": velocities.tolist()},
        "seed": seed,
        "softarm_version": __version__,
        "config": config.to_dict(),
    }


class RecordingWriter:
    """One open recording. Use `close(complete)` to finish it or `discard()` to remove it."""

    def __init__(self, path: Path, model: dict[str, Any], frame_dt: float):
        self.path = Path(path)
        self.part = self.path.with_name(self.path.name + ".part")
        self.frame_dt = frame_dt
        self.frames = 0
        self._file = open(self.part, "wb")
        self._writer = Writer(self._file, compression=CompressionType.ZSTD)
        self._writer.start(profile="", library=f"softarm/{__version__}")
        image_schema = self._writer.register_schema(
            "foxglove.RawImage", "protobuf", build_file_descriptor_set(RawImage).SerializeToString())
        self._channels = {IMAGE: self._writer.register_channel(IMAGE, "protobuf", image_schema)}
        for topic, (name, schema) in JSON_SCHEMAS.items():
            schema_id = self._writer.register_schema(name, "jsonschema", schema)
            self._channels[topic] = self._writer.register_channel(topic, "json", schema_id)
        self._writer.add_metadata(META_MODEL, {"format": FORMAT, "model": orjson.dumps(model).decode()})
        self._image = RawImage(frame_id="camera", encoding="mono8")

    def write(self, images: np.ndarray, stretch: np.ndarray, positions: np.ndarray, displacement: np.ndarray) -> None:
        """Append a block of frames: images (B, H, W) of 0/1, stretch (B, P), positions (B, N, 2), displacement (B,)."""
        n, height, width = images.shape
        self._image.width, self._image.height, self._image.step = width, height, width
        pixels = (images.astype(np.uint8) * 255).reshape(n, -1)
        positions = np.round(positions, POSITION_DECIMALS)  # a fresh C-contiguous array, as orjson needs
        stretch = np.ascontiguousarray(stretch, np.float64)
        k = np.arange(self.frames, self.frames + n)
        stamps = np.round(k * self.frame_dt * 1e9).astype(np.int64).tolist()
        add, ch = self._writer.add_message, self._channels
        for f, ns in enumerate(stamps):
            t = ns / 1e9
            self._image.timestamp.FromNanoseconds(ns)
            self._image.data = pixels[f].tobytes()
            add(ch[IMAGE], ns, self._image.SerializeToString(), ns)
            add(ch[STRETCH], ns, orjson.dumps({"t": t, "stretch": stretch[f]}, option=orjson.OPT_SERIALIZE_NUMPY), ns)
            add(ch[NODES], ns, orjson.dumps({"t": t, "positions": positions[f]}, option=orjson.OPT_SERIALIZE_NUMPY), ns)
            add(ch[EXCITATION], ns, orjson.dumps({"t": t, "displacement": float(displacement[f])}), ns)
        self.frames += n

    def close(self, complete: bool) -> Path:
        """Write the run record, the summary and the index, then move the file to its final name."""
        self._writer.add_metadata(META_RUN, {"complete": "true" if complete else "false", "frames": str(self.frames)})
        self._writer.finish()
        self._file.close()
        os.replace(self.part, self.path)
        return self.path

    def discard(self) -> None:
        """Drop the unfinished file: a failed run leaves nothing behind."""
        self._file.close()
        self.part.unlink(missing_ok=True)
