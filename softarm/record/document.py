"""The model document of a recording, checked before anything reads it: the keys and shapes every reader
relies on, so that a damaged or foreign document is refused in one line instead of failing deep inside."""

from pathlib import Path
from typing import Any, Callable

import numpy as np

from softarm.errors import RecordingError
from softarm.record.format import IMPORTED
from softarm.sensors import declared

MAX_PIXELS = 1 << 26  # per frame: a larger camera in a document is damage, not a camera


def check_model(model: Any, path: Path) -> dict[str, Any]:
    """`model` if it is a usable model document, else RecordingError naming what is wrong."""
    def require(ok: bool, what: str) -> None:
        if not ok:
            raise RecordingError(f"{path}: its model document is damaged ({what}); the recording cannot be read")

    require(isinstance(model, dict), "not a JSON object")
    camera = model.get("camera")
    require(isinstance(camera, dict), "no camera")
    height, width = camera.get("height"), camera.get("width")
    require(_int(height) and _int(width) and 0 < height * width <= MAX_PIXELS and height > 0, "camera size")
    if model.get("kind") == IMPORTED:
        return _check_imported(model, require)
    require(_numbers(camera.get("world_to_pixel"), (2, 3)), "camera map")
    nodes = model.get("nodes")
    require(_numbers(nodes, (None, 2)) and len(nodes) > 0, "nodes")
    for key in ("sensors", "springs"):
        require(_indices(model.get(key), len(nodes), 2), key)
    require(_indices(model.get("outline"), len(nodes), None), "outline")
    for kind in declared(model):  # the other sensor kinds' placements (softarm.sensors)
        require(_indices(model[kind.name], len(nodes), kind.width), kind.name)
    require(_int(model.get("seed", 0)) and model.get("seed", 0) >= 0, "seed")
    require(isinstance(model.get("excitation", {}), dict), "excitation")
    disturbances = model.get("disturbances", [])
    require(isinstance(disturbances, list) and all(isinstance(d, dict) for d in disturbances), "disturbances")
    return model


def _check_imported(model: dict[str, Any], require: Callable[[bool, str], None]) -> dict[str, Any]:
    """A robot log's recording: a camera without a known map, named sensors, a frame grid and its gaps."""
    sensors = model.get("sensors")
    require(isinstance(sensors, list) and len(sensors) > 0 and all(isinstance(s, str) for s in sensors), "sensors")
    frame_dt = model.get("frame_dt")
    require(isinstance(frame_dt, (int, float)) and not isinstance(frame_dt, bool) and 0 < frame_dt < 1e3, "frame_dt")
    gaps = model.get("gaps", [])
    require(isinstance(gaps, list) and all(_int(g) and g >= 0 for g in gaps), "gaps")
    require(isinstance(model.get("source", {}), dict), "source")
    return model


def _int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _numbers(value: Any, shape: tuple) -> bool:
    """A nested list of finite numbers of this shape (None: any length)."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        return False
    return (array.ndim == len(shape) and all(n is None or n == m for n, m in zip(shape, array.shape))
            and bool(np.isfinite(array).all()))


def _indices(value: Any, count: int, width: Any) -> bool:
    """A list of node indices in range, or of index tuples of `width`."""
    if not isinstance(value, list):
        return False
    flat = [v for item in value for v in (item if width is not None and isinstance(item, list) else [item])]
    shaped = width is None or all(isinstance(item, list) and len(item) == width for item in value)
    return shaped and all(_int(v) and 0 <= v < count for v in flat)
