"""The README's adaptation figures: a checkpoint, arms whose body changes for good at 10 s (a load on the tip row,
or a damaged segment), S seconds of camera after the change, and the imagination of 20-40 s (camera off) before
and after `softarm adapt`, beside the same arm's run without the change (what was lost).

    python docs/scripts/adaptation_study.py recordings/general.pt recordings/adaptation [--seeds 3] [--json out.json]

One core (torch's threads set to 1), as the issue asks; the recordings are made once in the folder.
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np

CHANGES = {  # the suite's harder levels, lasting from 10 s on
    "payload": {"kind": "payload", "mass": 0.015, "nodes": [54, 55, 56]},
    "damage": {"kind": "stiffness", "factor": 0.3},
}
SECONDS = (2.0, 5.0, 10.0)
CHANGE_AT, SCORED_FROM, DURATION = 10.0, 20.0, 40.0
SEED_BASE = 700_000  # below the suite's seeds, above the corpus's


def damaged_springs(rows: tuple[int, int]) -> list[int]:
    """Every spring with both ends in body rows rows[0]..rows[1] (3 nodes a row)."""
    from softarm.arm.body import build_body
    from softarm.config import load_config

    body = build_body(load_config())
    row = np.arange(len(body.rest)) // 3
    return [i for i, (a, b) in enumerate(body.springs) if rows[0] <= row[a] <= rows[1] and rows[0] <= row[b] <= rows[1]]


def recordings(folder: Path, seeds: int) -> dict[str, list[tuple[Path, Path]]]:
    """(changed, unchanged twin) per change and seed, simulated once."""
    from softarm.config import load_config
    from softarm.sim.simulate import simulate

    made: dict[str, list[tuple[Path, Path]]] = {}
    for name, change in CHANGES.items():
        spec = {**change, "start": CHANGE_AT}
        if name == "damage":
            spec = {"kind": "stiffness", "start": CHANGE_AT, "factor": change["factor"], "springs": damaged_springs((8, 10))}
        for seed in range(SEED_BASE, SEED_BASE + seeds):
            pair = (folder / f"{name}_{seed}.mcap", folder / f"{name}_{seed}_unchanged.mcap")
            for path, world in zip(pair, ([spec], [])):
                if not path.exists():
                    simulate(load_config(overrides={"run.duration": DURATION, "run.seed": seed,
                                                    "excitation.time_offset": float(seed % 97), "disturbances": world}),
                             path)
            made.setdefault(name, []).append(pair)
    return made


def scored_iou(checkpoint: Path, recording: Path) -> float:
    from softarm.imagine.replay_data import compute_replay

    replay = compute_replay(checkpoint, recording, nodes=False)
    chosen = (replay.times >= SCORED_FROM) & np.isfinite(replay.iou)
    return float(replay.iou[chosen].mean())


def main() -> None:
    import torch

    from softarm.learn.adapt import adapt

    parser = argparse.ArgumentParser()
    parser.add_argument("checkpoint", type=Path)
    parser.add_argument("folder", type=Path)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--json", type=Path)
    parser.add_argument("--png", type=Path)
    args = parser.parse_args()
    torch.set_num_threads(1)
    args.folder.mkdir(parents=True, exist_ok=True)
    rows = {}
    for name, pairs in recordings(args.folder, args.seeds).items():
        unchanged = np.mean([scored_iou(args.checkpoint, twin) for _, twin in pairs])
        before = np.mean([scored_iou(args.checkpoint, changed) for changed, _ in pairs])
        row = {"unchanged": unchanged, "before": before, "lost": unchanged - before, "after": {}, "recovered": {},
               "adapt_seconds": {}}
        for seconds in SECONDS:
            after, took = [], []
            for changed, _ in pairs:
                out = args.folder / f"{changed.stem}_{seconds:g}s.pt"
                clock = time.perf_counter()
                adapt(args.checkpoint, changed, seconds, out, force=True)
                took.append(time.perf_counter() - clock)
                after.append(scored_iou(out, changed))
            row["after"][seconds] = float(np.mean(after))
            row["recovered"][seconds] = float((np.mean(after) - before) / (unchanged - before))
            row["adapt_seconds"][seconds] = float(np.median(took))
        rows[name] = row
        print(name, json.dumps(row, indent=1))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    if args.png:
        plot(rows, args.png)


def plot(rows: dict, path: Path) -> None:
    """IoU of 20-40 s against the seconds of camera, per change, between the unadapted and the unchanged arm."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 3.8), dpi=120)
    for colour, (name, row) in zip(("#1f6fb4", "#d0452f"), rows.items()):
        ax.plot([0, *SECONDS], [row["before"], *row["after"].values()], "o-", color=colour, label=f"{name}: adapted")
        ax.axhline(row["unchanged"], color=colour, ls="--", lw=1, label=f"{name}: the arm unchanged")
    ax.set_xlabel("seconds of camera after the change (0: not adapted)")
    ax.set_ylabel("IoU of 20-40 s, camera off")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)


if __name__ == "__main__":
    main()
