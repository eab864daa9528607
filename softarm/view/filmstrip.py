"""Filmstrip PNGs: rows of frames at chosen times, for the README and for people without a viewer."""

from pathlib import Path
from typing import Any, Sequence, Union

import numpy as np
from PIL import Image, ImageDraw

from softarm.files import atomic_path
from softarm.view.images import DIFFERENCE_COLOURS, difference_codes

GAP = 2          # pixels between tiles, in image pixels before scaling
LABEL_WIDTH = 90  # pixels for the row labels, after scaling
HEADER = 14      # pixels for the time header, after scaling


def filmstrip(rows: Sequence[np.ndarray], labels: Sequence[str], times: Sequence[float], scale: int = 3) -> Image.Image:
    """One row per array of frames (T, H, W) or (T, H, W, 3), values in [0, 1]; one column per time."""
    tiles = []
    for frames in rows:
        frames = np.asarray(frames, np.float64)
        if frames.ndim == 3:
            frames = np.repeat(frames[..., None], 3, axis=-1)
        padded = np.pad(frames, ((0, 0), (GAP, GAP), (GAP, GAP), (0, 0)), constant_values=0.35)
        tiles.append(np.concatenate(list(padded), axis=1))
    grid = (np.clip(np.concatenate(tiles, axis=0), 0, 1) * 255).astype(np.uint8)
    grid = np.kron(grid, np.ones((scale, scale, 1), np.uint8))
    canvas = Image.new("RGB", (grid.shape[1] + LABEL_WIDTH, grid.shape[0] + HEADER), "white")
    canvas.paste(Image.fromarray(grid), (LABEL_WIDTH, HEADER))
    draw = ImageDraw.Draw(canvas)
    tile_h, tile_w = grid.shape[0] // len(rows), grid.shape[1] // len(times)
    for r, label in enumerate(labels):
        draw.text((4, HEADER + r * tile_h + tile_h // 2 - 6), label, fill="black")
    for c, t in enumerate(times):
        draw.text((LABEL_WIDTH + c * tile_w + 4, 1), f"t={t:.2f}s", fill="black")
    return canvas


def save_png(image: Image.Image, path: Union[str, Path]) -> Path:
    """Write atomically: the PNG appears whole or not at all."""
    with atomic_path(Path(path)) as part:
        image.save(part, format="PNG")
    return Path(path)


def replay_filmstrip(result: Any, columns: int = 8) -> Image.Image:
    """Rows camera / imagined / difference at evenly spaced imagined frames of a replay (the README's picture)."""
    frames = np.flatnonzero(result.predicted & result.recording.seen)  # a camera's gap has no frame to show
    picks = frames[np.linspace(0, len(frames) - 1, columns).round().astype(int)]
    truth = result.recording.frames[picks]
    rows = [truth, result.imagined[picks], DIFFERENCE_COLOURS[difference_codes(truth, result.imagined[picks])] / 255.0]
    return filmstrip(rows, ["camera", "imagined", "difference"], result.times[picks])
