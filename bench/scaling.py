"""Physics throughput against batch size, per Taichi backend, and where a GPU overtakes the CPU.

    python -m bench.scaling [--archs cpu gpu] [--arms 1 16 64 256 1024 4096] [--frames 20]

Each backend runs in its own process (Taichi starts once per process on one backend); a backend
that is not available is reported and skipped. Prints a Markdown table of spring updates per second
and writes it to bench/results/scaling.{md,json}.
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results"


def measure(arch: str, arms_list: list[int], frames: int) -> dict[int, float]:
    """Spring updates per second for each batch size on one backend (runs inside the child process)."""
    from softarm.config import load_config
    from softarm.sim.batch import arm_batch
    from softarm.sim.physics import Simulator
    from softarm.sim.runtime import init_taichi

    init_taichi(arch)
    config = load_config()
    i = config.integration
    rates = {}
    for arms in arms_list:
        batch = arm_batch(config, seeds=range(arms))
        sim = Simulator.from_config(config, batch, block_frames=frames)
        sim.step_block(frames)  # compile or load from the offline cache, warm up
        best = min(timed(lambda: sim.step_block(frames)) for _ in range(3))
        rates[arms] = arms * frames * i.substeps * len(batch.body.springs) / best
    return rates


def timed(action) -> float:
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--archs", nargs="+", default=["cpu", "gpu"])
    ap.add_argument("--arms", nargs="+", type=int, default=[1, 16, 64, 256, 1024, 4096])
    ap.add_argument("--frames", type=int, default=20, help="frames per timed block")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(measure(args.child, args.arms, args.frames)))
        return
    table: dict[str, dict[int, float]] = {}
    for arch in args.archs:
        run = subprocess.run([sys.executable, __file__, "--child", arch, "--frames", str(args.frames), "--arms",
                              *map(str, args.arms)], capture_output=True, text=True)
        if run.returncode != 0:
            print(f"{arch}: skipped ({run.stderr.strip().splitlines()[-1] if run.stderr.strip() else 'failed'})",
                  file=sys.stderr)
            continue
        table[arch] = {int(k): v for k, v in json.loads(run.stdout.strip().splitlines()[-1]).items()}
    archs = list(table)
    lines = ["| arms | " + " | ".join(f"{a} (spring updates/s)" for a in archs) + " |",
             "|---:|" + "---:|" * len(archs)]
    for arms in args.arms:
        lines.append(f"| {arms} | " + " | ".join(f"{table[a][arms]:.3g}" for a in archs) + " |")
    if {"cpu", "gpu"} <= set(table):
        over = next((n for n in args.arms if table["gpu"][n] > table["cpu"][n]), None)
        lines.append(f"\nThe GPU overtakes the CPU at {over} arms." if over
                     else "\nThe GPU never overtakes the CPU here.")
    text = "\n".join(lines)
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "scaling.md").write_text(text + "\n")
    (RESULTS / "scaling.json").write_text(json.dumps(table, indent=1))


if __name__ == "__main__":
    main()
