"""Makes docs/images/world_filmstrip.png: the world acting on the arm, camera frames of a contact and of a push with the
obstacle (orange) and the pushed nodes while pushed (red) drawn over them.

    python docs/scripts/make_world_picture.py
"""

import tempfile
from pathlib import Path

import numpy as np

from softarm.config import load_config
from softarm.record.reader import read_recording
from softarm.sim.simulate import simulate
from softarm.view.filmstrip import filmstrip, save_png

SWING = {"excitation.kind": "sum_of_sines", "excitation.sum_of_sines.amplitudes": [0.0008],
         "excitation.sum_of_sines.frequencies": [1.48], "excitation.sum_of_sines.phases": [0.0]}  # the first mode
CONTACT = {"kind": "obstacle", "start": 0.0, "centre": [0.035, -0.15], "radius": 0.02}
PUSH = {"kind": "push", "start": 2.0, "end": 2.1, "force": [-0.08, 0.0], "nodes": [45, 46, 47]}
TIMES = np.linspace(1.95, 2.65, 8)


def coloured(rec, table, times) -> np.ndarray:
    """(T, H, W, 3) frames at `times`: the arm grey, an obstacle orange, pushed nodes red while pushed."""
    picks = np.searchsorted(rec.times, times)
    rgb = np.repeat(rec.frames[picks, ..., None].astype(float) * 0.85, 3, axis=-1)
    M = rec.world_to_pixel
    h, w = rec.frames.shape[1:]
    rows, cols = np.mgrid[0:h, 0:w]
    world = np.linalg.solve(M[:, :2], np.stack([cols.ravel() + 0.5 - M[0, 2], rows.ravel() + 0.5 - M[1, 2]]))
    if table["kind"] == "obstacle":
        inside = (np.hypot(world[0] - table["centre"][0], world[1] - table["centre"][1]) < table["radius"]).reshape(h, w)
        rgb[:, inside] = rgb[:, inside] * 0.3 + np.array([1.0, 0.55, 0.1]) * 0.7
    for frame, k in enumerate(picks):
        if table["kind"] == "push" and table["start"] <= rec.times[k] < table["end"]:
            for u, v in rec.positions[k, table["nodes"]] @ M[:, :2].T + M[:, 2]:
                rgb[frame, int(np.clip(v, 0, h - 1)), int(np.clip(u, 0, w - 1))] = (1.0, 0.1, 0.1)
    return rgb


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for name, table in (("contact", CONTACT), ("push", PUSH)):
            path = Path(folder) / f"{name}.mcap"
            simulate(load_config(overrides={"run.duration": 4.0, "disturbances": [table], **SWING}), path)
            rows.append(coloured(read_recording(path), table, TIMES))
    strip = filmstrip(rows, ["contact", "push"], TIMES)
    print(save_png(strip, Path(__file__).parents[1] / "images" / "world_filmstrip.png"))


if __name__ == "__main__":
    main()
