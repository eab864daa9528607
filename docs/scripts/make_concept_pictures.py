"""Makes the two pictures of docs/get-started/concepts.md from the default config (no simulation, no training):

- docs/images/arm_anatomy.png: the arm at rest hanging from its driven top row: nodes, springs, the four stretch
  sensors and the four muscle groups, beside the camera's 84 x 52 frame of the same arm.
- docs/images/pipeline.png: the data path, from the physics to what the arm imagines.

    python docs/scripts/make_concept_pictures.py
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import FancyArrowPatch, FancyBboxPatch  # noqa: E402

from softarm.arm.body import build_body  # noqa: E402
from softarm.arm.muscles import build_muscles  # noqa: E402
from softarm.arm.statics import hanging_equilibrium  # noqa: E402
from softarm.config import load_config  # noqa: E402

IMAGES = Path(__file__).resolve().parents[1] / "images"
SENSOR_COLOURS = ["#d62728", "#1f77b4", "#ff7f0e", "#2ca02c"]
MUSCLE_COLOURS = ["#9467bd", "#8c564b", "#e377c2", "#17becf"]


def raster(config, positions: np.ndarray, outline: np.ndarray) -> np.ndarray:
    """The camera's binary frame of the arm, by the even-odd rule on pixel centres (docs/model.md, Camera)."""
    cam = config.camera
    u = cam.pixels_per_metre * positions[outline, 0] + cam.origin[0]
    v = -cam.pixels_per_metre * positions[outline, 1] + cam.origin[1]
    from matplotlib.path import Path as Polygon
    rows, cols = np.mgrid[0:cam.height, 0:cam.width]
    centres = np.stack([cols.ravel() + 0.5, rows.ravel() + 0.5], axis=1)
    return Polygon(np.stack([u, v], axis=1)).contains_points(centres).reshape(cam.height, cam.width)


def anatomy(path: Path) -> None:
    config = load_config()
    body = build_body(config)
    muscles = build_muscles(config, body)
    x = hanging_equilibrium(body) * 1000  # mm
    fig, (ax, cam_ax) = plt.subplots(1, 2, figsize=(9, 6.4), gridspec_kw={"width_ratios": [1.7, 1]})
    for s, (i, j) in enumerate(body.springs):
        ax.plot(x[[i, j], 0], x[[i, j], 1], color="#bbbbbb", lw=0.8, zorder=1)
    for g, name in enumerate(muscles.names):  # each group drawn beside its edge, outward, as a band
        ends = body.springs[muscles.group == g]
        side = np.sign(x[ends[:, 0], 0].mean())
        for i, j in ends:
            ax.plot(x[[i, j], 0] + side * 5, x[[i, j], 1], color=MUSCLE_COLOURS[g], lw=5, alpha=0.6,
                    solid_capstyle="butt", zorder=2)
        mid = x[ends].reshape(-1, 2).mean(axis=0)
        ax.text(mid[0] + side * 10, mid[1], f"muscle\n{name}", color=MUSCLE_COLOURS[g], fontsize=8,
                ha="left" if side > 0 else "right", va="center")
    for k, (a, b) in enumerate(body.sensors):
        ax.annotate("", x[b], x[a], arrowprops=dict(arrowstyle="<->", color=SENSOR_COLOURS[k], lw=1.8,
                                                   shrinkA=0, shrinkB=0), zorder=3)
        mid = (x[a] + x[b]) / 2
        side = np.sign(mid[0])
        ax.text(mid[0] + side * 10, mid[1] - 22, f"stretch {k}\n(nodes {a}–{b})", color=SENSOR_COLOURS[k],
                fontsize=7.5, ha="left" if side > 0 else "right", va="center", zorder=5)
    free = body.free
    ax.scatter(x[free, 0], x[free, 1], s=10, color="black", zorder=4, label="node (10 g)")
    ax.scatter(x[~free, 0], x[~free, 1], s=40, marker="s", color="black", zorder=4, label="driven top row")
    ax.annotate("", (16, 5), (-16, 5), arrowprops=dict(arrowstyle="<->", color="black"))
    ax.text(0, 9, "drive: the top moves sideways", ha="center", fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlim(-60, 60)
    ax.set_ylim(-205, 15)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm), up")
    ax.set_title(f"{config.body.rows} x {config.body.columns} nodes, {len(body.springs)} springs and dampers")
    ax.legend(loc="lower left", fontsize=7.5, frameon=False)
    frame = raster(config, x / 1000, body.outline)
    cam_ax.imshow(frame, cmap="gray_r", interpolation="nearest")
    cam_ax.set_title(f"camera: {config.camera.height} x {config.camera.width} px, "
                     f"{1000 / config.camera.pixels_per_metre:g} mm each", fontsize=10)
    cam_ax.set_xticks([])
    cam_ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(path)


def box(ax, xy: tuple[float, float], text: str, colour: str) -> None:
    ax.add_patch(FancyBboxPatch((xy[0] - 0.95, xy[1] - 0.42), 1.9, 0.84, boxstyle="round,pad=0.05",
                                facecolor=colour, edgecolor="#444444"))
    ax.text(*xy, text, ha="center", va="center", fontsize=8.5)


def arrow(ax, start: tuple[float, float], end: tuple[float, float], label: str = "") -> None:
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=12, color="#444444"))
    if label:
        ax.text((start[0] + end[0]) / 2, (start[1] + end[1]) / 2 + 0.12, label, ha="center", fontsize=7.5,
                color="#444444")


def pipeline(path: Path) -> None:
    fig, ax = plt.subplots(figsize=(10, 3.6))
    world, learn, use = "#fde0c5", "#d6e4f0", "#dcedc8"
    box(ax, (1, 2), "physics\n(Taichi: 57 nodes,\nsprings, muscles, world)", world)
    box(ax, (3.3, 2), "sensors + camera\n(stretch, drive;\n84 x 52 frames)", world)
    box(ax, (5.6, 2), "recording\n(MCAP, one file\nper arm)", world)
    box(ax, (7.9, 3.0), "autoencoder\nframe -> 16-number code", learn)
    box(ax, (7.9, 1.0), "latent model\nstretch + drive -> code", learn)
    box(ax, (10.2, 2), "decoder\ncode -> imagined frame\n+ confidence, surprise", use)
    arrow(ax, (1.95, 2), (2.35, 2))
    arrow(ax, (4.25, 2), (4.65, 2))
    arrow(ax, (6.55, 2.2), (6.95, 2.9), "frames")
    arrow(ax, (6.55, 1.8), (6.95, 1.1), "signals")
    arrow(ax, (7.9, 2.58), (7.9, 1.42), "target codes")
    arrow(ax, (8.85, 1.1), (9.25, 1.8), "imagined code")
    ax.text(6.2, 0.1, "train: softarm corpus / sim, then softarm train", ha="center", fontsize=8, style="italic")
    ax.text(10.2, 0.9, "use: replay, evaluate,\nstreamer, envs", ha="center", fontsize=8, style="italic")
    ax.set_xlim(-0.1, 11.3)
    ax.set_ylim(0, 3.6)
    ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    anatomy(IMAGES / "arm_anatomy.png")
    pipeline(IMAGES / "pipeline.png")
