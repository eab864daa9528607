"""`softarm import --preview`: a few camera frames beside the masks the import makes of them, so a user can tune
the segmentation (rule, background, region of interest) before converting a whole log."""

from pathlib import Path
from typing import Sequence

import numpy as np
from PIL import Image, ImageDraw

TILE = 240  # px: the width of each camera tile


def preview_image(examples: Sequence[tuple[np.ndarray, np.ndarray]], caption: str) -> Image.Image:
    """One row per example: the region of interest with the mask's outline tinted on it, and the mask itself
    at the models' camera size (enlarged, pixels kept square)."""
    rows = []
    for pixels, mask in examples:
        h = round(TILE * pixels.shape[0] / pixels.shape[1])
        camera = Image.fromarray(pixels).resize((TILE, h), Image.Resampling.BILINEAR)
        big = np.asarray(Image.fromarray(mask * 255).resize((TILE, h), Image.Resampling.NEAREST)) > 127
        tinted = np.asarray(camera).copy()
        tinted[big] = (0.5 * tinted[big] + 0.5 * np.array([40, 220, 255])).astype(np.uint8)
        row = Image.new("RGB", (3 * TILE + 20, h), "white")
        row.paste(camera, (0, 0))
        row.paste(Image.fromarray(tinted), (TILE + 10, 0))
        row.paste(Image.fromarray(np.where(big, 255, 0).astype(np.uint8)).convert("RGB"), (2 * TILE + 20, 0))
        rows.append(row)
    width, height = rows[0].width, sum(r.height + 6 for r in rows) + 24
    sheet = Image.new("RGB", (width, height), "white")
    ImageDraw.Draw(sheet).text((4, 4), caption + "   (camera | mask over it | mask at the models' size)", fill="black")
    y = 24
    for row in rows:
        sheet.paste(row, (0, y))
        y += row.height + 6
    return sheet


def write_preview(path: Path, examples: Sequence[tuple[np.ndarray, np.ndarray]], caption: str) -> Path:
    from softarm.files import atomic_path

    with atomic_path(path) as part:
        preview_image(examples, caption).save(part, format="PNG")
    return path
