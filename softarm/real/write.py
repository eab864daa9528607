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


def write_imported(path: Path, times: np.ndarray, frame_dt: float, frames: np.ndarray, seen: np.ndarray, stretch: np.ndarray,
                   drive: Optional[np.ndarray], sensors: list[str], settings: ImportSettings,
                   source: dict[str, Any]) -> Path:
    """One file, `.part` until closed; nothing is left behind if writing fails."""
    topics = {STRETCH: JSON_SCHEMAS[STRETCH], **({EXCITATION: JSON_SCHEMAS[EXCITATION]} if drive is not None else {})}
    model = {"kind": IMPORTED, "camera": {"width": settings.width, "height": settings.height, "world_to_pixel": None},
             "frame_dt": frame_dt,
             "sensors": sensors, "gaps": np.flatnonzero(~seen).tolist(), "seed": 0, "disturbances": [],
             "source": source, "softarm_version": __version__}
    mcap = McapFile(path, (IMAGE,), topics)
    try:
        mcap.writer.add_metadata(META_MODEL, {"format": FORMAT, "model": orjson.dumps(model).decode()})
        stamps = np.round(times * 1e9).astype(np.int64).tolist()
        pixels = (frames * 255).astype(np.uint8)
        for k, ns in enumerate(stamps):
            messages = {IMAGE: mcap.images(pixels[k:k + 1], [ns])} if seen[k] else {}
            messages[STRETCH] = [orjson.dumps({"t": ns / 1e9, "stretch": stretch[k].tolist()})]
            if drive is not None:
                messages[EXCITATION] = [orjson.dumps({"t": ns / 1e9, "displacement": float(drive[k])})]
            mcap.add_frames([ns], messages)
        return mcap.close({META_RUN: {"complete": "true", "frames": str(len(stamps))}})
    except BaseException:
        mcap.discard()
        raise
