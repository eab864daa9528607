"""Convergence study: error vs substeps, and the amplitude where the motion stops being reproducible.

For each substep count n, the run is compared with a 4x finer run (4n): the largest node distance
over the whole run is the error the default must keep below 0.1 mm (MODEL.md, Integration). The
amplitude sweep repeats the comparison at the default substeps for growing amplitudes: once the
motion turns chaotic, step-size round-off grows to the size of the arm and runs stop agreeing.

    python bench/convergence.py [--duration 100] [--config FILE]
"""

import argparse
import time

import numpy as np

from softarm.body import build_body, hanging_equilibrium
from softarm.config import load_config
from softarm.excitation import Drive
from softarm.physics import Simulator
from softarm.runtime import init_taichi


def run(body, drives, config, substeps: int, n_frames: int) -> np.ndarray:
    x0 = hanging_equilibrium(body)
    sim = Simulator(body, drives, config.integration.frame_dt, substeps, config.integration.blowup_distance,
                    x0, np.zeros_like(x0))
    return sim.advance(n_frames)


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
    body = build_body(config)
    n_frames = round(args.duration / config.integration.frame_dt)
    e = config.excitation
    default = Drive(e.amplitude, tuple(e.frequencies), e.time_offset)

    print(f"error vs substeps (A = {e.amplitude} m, {args.duration} s): max node distance to a 4x finer run")
    print("| substeps | step (ms) | error (mm) | tip range x (mm) |")
    print("|---:|---:|---:|---:|")
    for n in args.substeps:
        start = time.perf_counter()
        coarse, fine = run(body, [default], config, n, n_frames), run(body, [default], config, 4 * n, n_frames)
        tip = coarse[0, :, body.outline[len(body.outline) // 2 - 1], 0]
        print(f"| {n} | {1e3 * config.integration.frame_dt / n:.3f} | {1e3 * max_error(coarse, fine)[0]:.4f} "
              f"| {1e3 * tip.min():.1f} .. {1e3 * tip.max():.1f} |  ({time.perf_counter() - start:.1f} s)")

    n = config.integration.substeps
    drives = [Drive(a, tuple(e.frequencies), e.time_offset) for a in args.amplitudes]
    coarse, fine = run(body, drives, config, n, n_frames), run(body, drives, config, 4 * n, n_frames)
    errors = max_error(coarse, fine)
    reach = np.abs(coarse[..., 0]).max(axis=(1, 2))
    print(f"\namplitude sweep at substeps = {n} vs {4 * n} ({args.duration} s)")
    print("| amplitude (mm) | error (mm) | widest node excursion |x| (mm) |")
    print("|---:|---:|---:|")
    for a, err, r in zip(args.amplitudes, errors, reach):
        print(f"| {1e3 * a:.1f} | {1e3 * err:.4f} | {1e3 * r:.1f} |")


if __name__ == "__main__":
    main()
