"""Filmstrip PNGs: rows of frames at chosen times, for the README and for people without a viewer."""

from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np
from PIL import Image, ImageDraw

from softarm.errors import BlindRangeError
from softarm.files import atomic_path
from softarm.view.images import DIFFERENCE_COLOURS, difference_codes

GAP = 2          # pixels between tiles, in image pixels before scaling
LABEL_WIDTH = 90  # pixels for the row labels, after scaling
HEADER = 14      # pixels for the time header, after scaling


def filmstrip(rows: Sequence[np.ndarray], labels: Sequence[str], times: Sequence[float], scale: int = 3,
              notes: Optional[Sequence[str]] = None) -> Image.Image:
    """One row per array of frames (T, H, W) or (T, H, W, 3), values in [0, 1]; one column per time, with a
    second header line of `notes` where given."""
    tiles = []
    for frames in rows:
        frames = np.asarray(frames, np.float64)
        if frames.ndim == 3:
            frames = np.repeat(frames[..., None], 3, axis=-1)
        padded = np.pad(frames, ((0, 0), (GAP, GAP), (GAP, GAP), (0, 0)), constant_values=0.35)
        tiles.append(np.concatenate(list(padded), axis=1))
    grid = (np.clip(np.concatenate(tiles, axis=0), 0, 1) * 255).astype(np.uint8)
    grid = np.kron(grid, np.ones((scale, scale, 1), np.uint8))
    header = HEADER * (2 if notes else 1)
    canvas = Image.new("RGB", (grid.shape[1] + LABEL_WIDTH, grid.shape[0] + header), "white")
    canvas.paste(Image.fromarray(grid), (LABEL_WIDTH, header))
    draw = ImageDraw.Draw(canvas)
    tile_h, tile_w = grid.shape[0] // len(rows), grid.shape[1] // len(times)
    for r, label in enumerate(labels):
        draw.text((4, header + r * tile_h + tile_h // 2 - 6), label, fill="black")
    for c, t in enumerate(times):
        draw.text((LABEL_WIDTH + c * tile_w + 4, 1), f"t={t:.2f}s", fill="black")
        if notes:
            draw.text((LABEL_WIDTH + c * tile_w + 4, HEADER), notes[c], fill="black")
    return canvas


def save_png(image: Image.Image, path: Union[str, Path]) -> Path:
    """Write atomically: the PNG appears whole or not at all."""
    with atomic_path(Path(path)) as part:
        image.save(part, format="PNG")
    return Path(path)


def replay_filmstrip(result: Any, columns: int = 8, span: Optional[tuple[float, float]] = None) -> Image.Image:
    """Rows camera / imagined / difference at evenly spaced imagined frames of a replay (within `span`, seconds,
    where given): the README's picture. With a surprise, a fourth row shows the alarm (the arm red while it is
    on) and the header each frame's surprise."""
    frames = np.flatnonzero(result.predicted & result.recording.seen)  # a camera's gap has no frame to show
    if span is not None:
        frames = frames[(result.times[frames] >= span[0]) & (result.times[frames] <= span[1])]
        if not len(frames):
            raise BlindRangeError(f"--png-span {span[0]:g}:{span[1]:g} holds no imagined frame of "
                                  f"{result.recording.path}")
    picks = frames[np.linspace(0, len(frames) - 1, columns).round().astype(int)]
    truth = result.recording.frames[picks]
    rows = [truth, result.imagined[picks], DIFFERENCE_COLOURS[difference_codes(truth, result.imagined[picks])] / 255.0]
    labels, notes = ["camera", "imagined", "difference"], None
    if np.isfinite(result.surprise[picks]).any():
        colour = np.where(result.alarm[picks, None], [0.85, 0.1, 0.1], [0.6, 0.6, 0.6])[:, None, None, :]
        rows.append(np.where(result.imagined[picks, ..., None] >= 0.5, colour, 1.0))
        labels.append("alarm")
        notes = [f"surprise {v:.1f}" for v in result.surprise[picks]]
    return filmstrip(rows, labels, result.times[picks], notes=notes)
