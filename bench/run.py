"""softarm benchmarks: every figure is a ratio against a reference measured in the same run.

    python -m bench.run [--quick] [--out bench/results]

Prints a Markdown table and writes it, with the raw figures, to bench/results/latest.{md,json}.
Sections: physics (Taichi vs the float64 NumPy reference), physics vs C (Taichi on every core vs
hand-written serial C -O3 on one core, bench/physics_reference.c), rasteriser (Taichi vs cv2.fillPoly),
the recorder's C encoder (vs its Python encoder, bench/recording.py), end to end (`softarm sim` with
defaults, start-up included, vs real time), and batches end to end
(`softarm sim --arms 64|256 --duration 10`, files written, vs the C loop's physics time for the same work, and
the 64-arm command's start-up alone against the same C time: the floor under that ratio).
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

import cv2
import numpy as np

from bench.c_reference import CReference, find_compiler
from bench.recording import encoder_rows
from softarm.arm.camera import world_to_pixel
from softarm.arm.reference import simulate_reference
from softarm.config import load_config, override
from softarm.sim.batch import arm_batch
from softarm.sim.budget import MAX_BLOCK_FRAMES
from softarm.sim.physics import Simulator
from softarm.sim.raster import Rasteriser
from softarm.sim.runtime import init_taichi
from softarm.sim.simulate import simulate


def best_of(repeats: int, action: Callable[[], object]) -> float:
    """Shortest wall time of `repeats` runs: the least disturbed by the other load on a shared machine."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return min(times)


def row(name: str, ours: float, reference: float, unit: str, against: str) -> dict:
    return {"name": name, "ours": ours, "reference": reference, "unit": unit, "against": against,
            "ratio": ours / reference}


def physics_rows(config, quick: bool) -> list[dict]:
    one = arm_batch(config, seeds=[0])
    i = config.integration
    springs = len(one.body.springs)
    ref_frames = 5 if quick else 20
    numpy_s = best_of(3, lambda: simulate_reference(one.body, one.drives[0], one.positions[0], one.velocities[0],
                                                    i.frame_dt, i.substeps, ref_frames + 1))
    numpy_rate = ref_frames * i.substeps * springs / numpy_s  # spring updates per second, one arm
    rows = []
    for arms in (1, 64):
        sim = Simulator.from_config(config, arm_batch(config, seeds=range(arms)))
        sim.step_block(1)  # compile (or load from the offline cache) outside the timing
        blocks = 1 if quick or arms > 1 else 10
        seconds = best_of(3, lambda: [sim.step_block(100) for _ in range(blocks)])
        rate = arms * blocks * 100 * i.substeps * springs / seconds
        rows.append(row(f"physics, {arms} arm{'s' if arms > 1 else ''}", rate, numpy_rate,
                        "spring updates/s", "NumPy reference (float64, arms one after another)"))
    return rows


def disturbance_rows(config, quick: bool) -> list[dict]:
    """64 arms with one disturbance of each kind, all four active the whole time, against the same arms without
    any (whose kernel is compiled without their code): what the world costs when it acts."""
    world = [{"kind": "push", "start": 0.0, "force": [0.01, 0.0], "nodes": [54, 55, 56]},
             {"kind": "payload", "start": 0.0, "mass": 0.005, "nodes": [54, 55, 56]},
             {"kind": "stiffness", "start": 0.0, "factor": 0.5, "springs": list(range(40, 60))},
             {"kind": "obstacle", "start": 0.0, "centre": [0.05, -0.15], "radius": 0.02}]
    blocks = 1 if quick else 5
    rates = []
    for tables in (world, []):
        c = override(config, {"disturbances": tables})
        sim = Simulator.from_config(c, arm_batch(c, seeds=range(64)))
        sim.step_block(1)  # compile (or load from the offline cache) outside the timing
        rates.append(64 * blocks * 100 * c.integration.substeps * len(sim.body.springs)
                     / best_of(3, lambda: [sim.step_block(100) for _ in range(blocks)]))
        sim.close()
    return [row("physics, 64 arms, every kind of disturbance acting", rates[0], rates[1], "spring updates/s",
                "the same arms undisturbed")]


def c_reference_rows(config, quick: bool) -> list[dict]:
    """Taichi's batch throughput (all cores) against the hand-written C loop on one core; and C against NumPy.

    The C loop steps arms one after another, so its 1-arm rate is its rate for any batch: every row
    divides by that one figure. Each measurement covers about the same number of spring updates, so
    big batches run fewer frames (in blocks of 100, as `softarm sim` steps them).
    """
    if find_compiler() is None:
        print("physics vs C: skipped, no C compiler (cc or gcc) on PATH", file=sys.stderr)
        return []
    one = arm_batch(config, seeds=[0])
    i = config.integration
    per_frame = i.substeps * len(one.body.springs)  # spring updates per arm and frame
    target, repeats = (2e7, 1) if quick else (1e8, 3)  # spring updates per measurement: ~0.2 s / ~1-2 s
    against = "hand-written C -O3, one core"

    def frames_for(arms: int) -> int:
        return max(10, round(target / (arms * per_frame)))

    def in_blocks(step: Callable[[int], object], frames: int) -> None:
        for start in range(0, frames, 100):
            step(min(100, frames - start))

    c_rate = c_reference_rate(config, frames_for(1))  # the divisor of every row
    numpy_frames = 5 if quick else 20
    numpy_s = best_of(3, lambda: simulate_reference(one.body, one.drives[0], one.positions[0], one.velocities[0],
                                                    i.frame_dt, i.substeps, numpy_frames + 1))
    rows = [row("physics, 1 arm, C vs NumPy", c_rate, numpy_frames * per_frame / numpy_s, "spring updates/s",
                "NumPy reference (float64)")]
    for arms in (1, 16, 64, 256):
        sim = Simulator.from_config(config, arm_batch(config, seeds=range(arms)))
        frames = frames_for(arms)
        sim.step_block(min(100, frames))  # compile (or load from the offline cache) and warm up outside the timing
        seconds = best_of(repeats, lambda: in_blocks(sim.step_block, frames))
        rows.append(row(f"physics vs C, {arms} arm{'s' if arms > 1 else ''}", arms * frames * per_frame / seconds,
                        c_rate, "spring updates/s", against))
    return rows


def c_reference_rate(config, frames: int) -> float:
    """Spring updates per second of the serial C loop on one arm (its rate for any batch: arms run in turn)."""
    one = arm_batch(config, seeds=[0])
    c = CReference.from_config(config, one)
    c.advance(100)  # warm up caches and the drive's first cycle outside the timing
    seconds = best_of(3, lambda: [c.advance(min(100, frames - start)) for start in range(0, frames, 100)])
    return frames * config.integration.substeps * len(one.body.springs) / seconds


def batch_rows(config, quick: bool) -> list[dict]:
    """`softarm sim --arms N --duration 10`, files written, start-up included, against the time the serial C
    loop needs for the same physics (arms x frames x substeps x springs at its measured rate)."""
    if find_compiler() is None:
        print("batch vs C: skipped, no C compiler (cc or gcc) on PATH", file=sys.stderr)
        return []
    duration = 2.0 if quick else 10.0
    springs = len(arm_batch(config, seeds=[0]).body.springs)
    c_rate = c_reference_rate(config, 300 if quick else 2000)
    softarm = str(Path(sys.executable).with_name("softarm"))
    rows = []
    for arms in ((64,) if quick else (64, 256)):
        c_seconds = (arms * round(duration / config.integration.frame_dt) * config.integration.substeps * springs
                     / c_rate)
        rows.append(row(f"softarm sim --arms {arms} --duration {duration:g}, files written (start-up included)",
                        sim_seconds(softarm, arms, duration, 1 if quick else 2), c_seconds, "s",
                        "serial C physics time for the same arms and seconds (lower is better)"))
        if arms == 64:  # the floor under that ratio: the same command with almost nothing to simulate
            rows.append(row("softarm sim --arms 64 --duration 0.02, start-up and two frames", sim_seconds(
                softarm, arms, 0.02, 1 if quick else 3), c_seconds, "s", "the row above's C physics time"))
    return rows


def sim_seconds(softarm: str, arms: int, duration: float, repeats: int) -> float:
    """Best wall time of `softarm sim --arms ARMS --duration D` writing its files, after one run that compiles the
    batch shape's kernel (Taichi's offline cache has it for the timed runs)."""
    with tempfile.TemporaryDirectory() as folder:
        args = [softarm, "sim", "--arms", str(arms), "--duration", str(duration), "--out", "b.mcap", "-q"]
        subprocess.run(args, cwd=folder, check=True)
        return best_of(repeats, lambda: subprocess.run([*args, "--force"], cwd=folder, check=True))


def raster_rows(config, quick: bool) -> list[dict]:
    one = arm_batch(config, seeds=[0])
    frames = MAX_BLOCK_FRAMES  # the block `softarm sim` draws per kernel launch
    sim = Simulator.from_config(config, one, block_frames=frames)
    sim.step_block(frames)
    history = sim.history.copy()
    camera = Rasteriser(config.camera, one.body.outline, 1, frames)
    camera.render(sim.history, frames)
    repeats = 3 if quick else 10
    ours = best_of(repeats, lambda: camera.render(sim.history, frames))
    M = world_to_pixel(config.camera)
    image = np.zeros((config.camera.height, config.camera.width), np.uint8)

    def with_cv2() -> None:
        for f in range(frames):
            polygon = history[0, f, one.body.outline] @ M[:, :2].T + M[:, 2] - 0.5  # cv2: integer = pixel centre
            image[:] = 0
            cv2.fillPoly(image, [np.round(polygon * 256).astype(np.int32)], 1, lineType=cv2.LINE_8, shift=8)

    reference = best_of(repeats, with_cv2)
    return [row("rasteriser, 1 arm", frames / ours, frames / reference, "frames/s", "cv2.fillPoly (8-bit subpixel)")]


def end_to_end_rows(quick: bool) -> list[dict]:
    duration = 10.0 if quick else 100.0
    softarm = str(Path(sys.executable).with_name("softarm"))
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        subprocess.run([softarm, "sim", "--duration", str(duration), "--out", "run.mcap", "--quiet"], cwd=folder,
                       check=True)
        seconds = time.perf_counter() - start
    return [row(f"softarm sim, {duration:g} s default run (start-up included)", duration / seconds, 1.0,
                "x real time", "real time")]


def stage_table(quick: bool) -> str:
    """Where one in-process default run spends its time, so the slowest stage is visible."""
    duration = 10.0 if quick else 100.0
    with tempfile.TemporaryDirectory() as folder:
        result = simulate(load_config(overrides={"run.duration": duration}), Path(folder) / "run.mcap")
    lines = [f"Stages of one {duration:g} s default run in process ({result.wall_seconds:.2f} s, "
             f"{result.real_time_factor:.0f}x real time, Taichi already started):", "",
             "| stage | seconds | share |", "|---|---:|---:|"]
    for stage, seconds in sorted(result.stage_seconds.items(), key=lambda kv: -kv[1]):
        lines.append(f"| {stage} | {seconds:.3f} | {seconds / result.wall_seconds:.0%} |")
    return "\n".join(lines)


def to_markdown(rows: list[dict]) -> str:
    lines = ["| benchmark | softarm | reference | ratio | against |", "|---|---:|---:|---:|---|"]
    for r in rows:
        lines.append(f"| {r['name']} | {r['ours']:,.4g} {r['unit']} | {r['reference']:,.4g} | "
                     f"**{r['ratio']:,.1f}x** | {r['against']} |")
    return "\n".join(lines)


def machine() -> str:
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
               platform.processor()) if os.path.exists("/proc/cpuinfo") else platform.processor()
    return f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer frames and repeats (a smoke test)")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    args = ap.parse_args()
    init_taichi("cpu")
    config = load_config()
    rows = (physics_rows(config, args.quick) + disturbance_rows(config, args.quick)
            + c_reference_rows(config, args.quick) + raster_rows(config, args.quick) + encoder_rows(config, args.quick)
            + end_to_end_rows(args.quick) + batch_rows(config, args.quick))
    table = to_markdown(rows) + "\n\n" + stage_table(args.quick)
    print(f"machine: {machine()}\n\n{table}")
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "latest.md").write_text(f"Measured on {machine()}.\n\n{table}\n")
    (args.out / "latest.json").write_text(json.dumps({"machine": machine(), "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
