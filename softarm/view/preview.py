"""`softarm import --preview`: a few camera frames beside the masks the import makes of them, so a user can tune
the segmentation (rule, background, region of interest) before converting a whole log."""

from pathlib import Path
from typing import Sequence

import numpy as np
from PIL import Image, ImageDraw

HEIGHT = 220  # px: the height of each tile
GAP = 6


def example_strip(frame: np.ndarray, pixels: np.ndarray, mask: np.ndarray) -> Image.Image:
    """The whole frame with its region of interest outlined, the mask tinted over that region, and the mask at
    the models' camera size (enlarged, its pixels kept square), side by side."""
    width = max(1, round(HEIGHT * pixels.shape[1] / pixels.shape[0]))
    whole = Image.fromarray(frame).resize((max(1, round(HEIGHT * frame.shape[1] / frame.shape[0])), HEIGHT),
                                          Image.Resampling.BILINEAR)
    camera = Image.fromarray(pixels).resize((width, HEIGHT), Image.Resampling.BILINEAR)
    big = np.asarray(Image.fromarray(mask * 255).resize((width, HEIGHT), Image.Resampling.NEAREST)) > 127
    tinted = np.asarray(camera).copy()
    tinted[big] = (0.45 * tinted[big] + 0.55 * np.array([40, 220, 255])).astype(np.uint8)
    tiles = (whole, Image.fromarray(tinted), Image.fromarray(np.where(big, 255, 0).astype(np.uint8)))
    strip = Image.new("RGB", (sum(t.width for t in tiles) + 2 * GAP, HEIGHT), "white")
    x = 0
    for tile in tiles:
        strip.paste(tile.convert("RGB"), (x, 0))
        x += tile.width + GAP
    return strip


def preview_image(examples: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], caption: str) -> Image.Image:
    """The examples left to right, each as camera | mask over it | mask at the models' size, under a caption."""
    strips = [example_strip(*example) for example in examples]
    sheet = Image.new("RGB", (sum(s.width + 3 * GAP for s in strips) + GAP, HEIGHT + 30), "white")
    ImageDraw.Draw(sheet).text((GAP, 6), caption + "   (each frame: camera and its region of interest | "
                                                   "mask over it | mask at the models' size)",
                               fill="black")
    x = GAP
    for strip in strips:
        sheet.paste(strip, (x, 26))
        x += strip.width + 3 * GAP
    return sheet


def write_preview(path: Path, examples: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]], caption: str) -> Path:
    from softarm.files import atomic_path

    with atomic_path(path) as part:
        preview_image(examples, caption).save(part, format="PNG")
    return path
