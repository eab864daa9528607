"""Makes docs/images/imagining.gif, the README's picture: the arm as the camera sees it, as the model imagines it
from its stretch sensors with the camera off, and their difference, over two seconds of a replay's blackout.

    python docs/scripts/make_imagination_gif.py recordings/demo/model.pt recordings/demo/seed0.mcap --start 95
"""

import argparse
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

import softarm
from softarm.view.images import DIFFERENCE_COLOURS, difference_codes

SCALE, GAP, HEADER = 3, 6, 18


def panel(frames: np.ndarray) -> np.ndarray:
    """(T, H, W) in [0, 1] as (T, H*SCALE, W*SCALE, 3) bytes."""
    grey = (np.clip(frames, 0, 1) * 255).astype(np.uint8).repeat(SCALE, 1).repeat(SCALE, 2)
    return np.repeat(grey[..., None], 3, axis=-1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkpoint")
    parser.add_argument("recording")
    parser.add_argument("--start", type=float, default=95.0, help="s: the camera goes off here")
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "images" / "imagining.gif")
    args = parser.parse_args()
    end = args.start + args.seconds
    replayed = softarm.replay(args.checkpoint, args.recording, blind=[f"{args.start:g}:{end:g}"]).replay
    times = replayed.recording.times
    picks = np.flatnonzero((times >= args.start) & (times < end))[::2]  # 50 frames a second
    truth, imagined = replayed.recording.frames[picks], replayed.imagined[picks]
    difference = DIFFERENCE_COLOURS[difference_codes(truth, imagined)].repeat(SCALE, 1).repeat(SCALE, 2)
    tiles = [panel(truth.astype(float)), panel(imagined), difference]
    h, w = tiles[0].shape[1:3]
    images = []
    for k, t in enumerate(times[picks]):
        canvas = Image.new("RGB", (3 * w + 2 * GAP, h + HEADER), "white")
        draw = ImageDraw.Draw(canvas)
        for i, (tile, label) in enumerate(zip(tiles, ("camera", "imagined (camera off)", "difference"))):
            canvas.paste(Image.fromarray(tile[k]), (i * (w + GAP), HEADER))
            draw.text((i * (w + GAP) + 2, 3), label, fill="black")
        draw.text((3 * w + 2 * GAP - 48, 3), f"{t:6.2f} s", fill="black")
        images.append(canvas)
    images[0].save(args.out, save_all=True, append_images=images[1:], duration=40, loop=0, optimize=True)
    print(args.out, f"{len(images)} frames, IoU {np.nanmean(replayed.iou[picks]):.3f}")


if __name__ == "__main__":
    main()
