"""Convergence study: error vs substeps, and the amplitude where the motion stops being reproducible.

For each substep count n, the run is compared with a 4x finer run (4n): the largest node distance
over the whole run is the error the default must keep below 0.1 mm (docs/model.md, Integration). The
amplitude sweep repeats the comparison at the default substeps for growing amplitudes: once the
motion turns chaotic, step-size round-off grows to the size of the arm and runs stop agreeing.

    python -m bench.convergence [--duration 100] [--config FILE]
"""

import argparse
import time

import numpy as np

from softarm.config import load_config, override
from softarm.sim.batch import ArmBatch, arm_batch
from softarm.sim.physics import Simulator
from softarm.sim.runtime import init_taichi


def run(config, amplitudes: list[float], substeps: int, n_frames: int) -> np.ndarray:
    """Seed 0 (the paper's run) at each amplitude, started as `softarm sim` starts it, stepped as one batch."""
    config = override(config, {"integration.substeps": substeps})
    arms = [arm_batch(override(config, {"excitation.amplitude": a}), seeds=[0]) for a in amplitudes]
    batch = ArmBatch(body=arms[0].body, seeds=[0] * len(arms), drives=[b.drives[0] for b in arms],
                     positions=np.concatenate([b.positions for b in arms]),
                     velocities=np.concatenate([b.velocities for b in arms]))
    return Simulator.from_config(config, batch).advance(n_frames)


def max_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Per arm: the largest distance of any node at any frame, m."""
    return np.linalg.norm(a - b, axis=-1).max(axis=(1, 2))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--duration", type=float, default=100.0)
    ap.add_argument("--config", default=None)
    ap.add_argument("--substeps", type=int, nargs="+", default=[12, 20, 40, 80])
    ap.add_argument("--amplitudes", type=float, nargs="+", default=[0.005, 0.01, 0.015, 0.02, 0.03, 0.04])
    args = ap.parse_args()
    init_taichi("cpu")
    config = load_config(args.config)
    outline = arm_batch(config, seeds=[0]).body.outline
    n_frames = round(args.duration / config.integration.frame_dt)
    e = config.excitation

    print(f"error vs substeps (A = {e.amplitude} m, {args.duration} s): max node distance to a 4x finer run")
    print("| substeps | step (ms) | error (mm) | tip range x (mm) |")
    print("|---:|---:|---:|---:|")
    for n in args.substeps:
        start = time.perf_counter()
        coarse, fine = run(config, [e.amplitude], n, n_frames), run(config, [e.amplitude], 4 * n, n_frames)
        tip = coarse[0, :, outline[len(outline) // 2 - 1], 0]
        print(f"| {n} | {1e3 * config.integration.frame_dt / n:.3f} | {1e3 * max_error(coarse, fine)[0]:.4f} "
              f"| {1e3 * tip.min():.1f} .. {1e3 * tip.max():.1f} |  ({time.perf_counter() - start:.1f} s)")

    n = config.integration.substeps
    coarse, fine = run(config, args.amplitudes, n, n_frames), run(config, args.amplitudes, 4 * n, n_frames)
    errors = max_error(coarse, fine)
    reach = np.abs(coarse[..., 0]).max(axis=(1, 2))
    print(f"\namplitude sweep at substeps = {n} vs {4 * n} ({args.duration} s)")
    print("| amplitude (mm) | error (mm) | widest node excursion |x| (mm) |")
    print("|---:|---:|---:|")
    for a, err, r in zip(args.amplitudes, errors, reach):
        print(f"| {1e3 * a:.1f} | {1e3 * err:.4f} | {1e3 * r:.1f} |")


if __name__ == "__main__":
    main()
