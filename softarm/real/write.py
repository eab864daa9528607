"""Writing an imported recording: softarm-recording/3 of kind `imported` (docs/recording.md): camera frames where
the camera had one, the stretch (and the drive) at every frame, the source and every setting in the metadata."""

from pathlib import Path
from typing import Any, Optional

import numpy as np
import orjson

from softarm import __version__
from softarm.real.settings import ImportSettings
from softarm.record.format import EXCITATION, FORMAT, IMAGE, IMPORTED, JSON_SCHEMAS, META_MODEL, META_RUN, STRETCH
from softarm.record.mcap_file import McapFile


def write_imported(path: Path, times: np.ndarray, frame_dt: float, frames: np.ndarray, seen: np.ndarray,
                   stretch: np.ndarray, drive: Optional[np.ndarray], sensors: list[str], settings: ImportSettings,
                   source: dict[str, Any]) -> Path:
    """One file, `.part` until closed; nothing is left behind if writing fails."""
    topics = {STRETCH: JSON_SCHEMAS[STRETCH], **({EXCITATION: JSON_SCHEMAS[EXCITATION]} if drive is not None else {})}
    scale = source["found"].get("pixels_per_metre")
    model = {"kind": IMPORTED, "camera": {"width": settings.width, "height": settings.height, "world_to_pixel": None,
                                          "pixels_per_metre": scale},
             "frame_dt": frame_dt,
             "sensors": sensors, "gaps": np.flatnonzero(~seen).tolist(), "seed": 0, "disturbances": [],
             "source": source, "softarm_version": __version__}
    mcap = McapFile(path, (IMAGE,), topics)
    try:
        mcap.writer.add_metadata(META_MODEL, {"format": FORMAT, "model": orjson.dumps(model).decode()})
        stamps = np.round(times * 1e9).astype(np.int64).tolist()
        images = iter(mcap.images((frames[seen] * 255).astype(np.uint8), [ns for ns, k in zip(stamps, seen) if k]))
        rows = stretch.tolist()
        channels, logged, data = [], [], []
        for k, ns in enumerate(stamps):  # a frame's messages in the order of the topics' table
            parts = [(IMAGE, next(images))] if seen[k] else []
            parts.append((STRETCH, orjson.dumps({"t": ns / 1e9, "stretch": rows[k]})))
            if drive is not None:
                parts.append((EXCITATION, orjson.dumps({"t": ns / 1e9, "displacement": float(drive[k])})))
            for topic, message in parts:
                channels.append(mcap.channels[topic])
                logged.append(ns)
                data.append(message)
        mcap.writer.add_messages(channels, logged, data)
        return mcap.close({META_RUN: {"complete": "true", "frames": str(len(stamps))}})
    except BaseException:
        mcap.discard()
        raise
