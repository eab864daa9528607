"""bench.gpu's physics and recording rows: throughput against batch size on each Taichi backend, the GPU's
recordings against the CPU's, and the whole `softarm sim` of a batch.

Taichi runs one backend per process, so each backend's rows are measured in a child process of its own.
"""

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

GPU_ARMS = (1, 64, 1024, 4096, 16384, 65536)
BLOCK_SECONDS = 4.0  # a CPU batch whose one block would take longer than this is not timed (the last rows would
#                      take minutes on a laptop); the table says so
WORLD = [{"kind": "push", "start": 1.0, "end": 3.0, "force": [0.02, 0.0], "nodes": [45, 46, 47]},
         {"kind": "payload", "start": 2.0, "mass": 0.005, "nodes": [54, 55, 56]},
         {"kind": "stiffness", "start": 4.0, "factor": 0.5, "springs": list(range(62, 68))},
         {"kind": "obstacle", "start": 0.0, "centre": [0.03, -0.16], "radius": 0.012}]
SOFTARM = str(Path(sys.executable).with_name("softarm"))


def scaling(arch: str, arms_list: list[int], frames: int) -> dict[int, float]:
    """Spring updates per second of each batch on one backend (in the child process): the best of three blocks of
    `frames` frames after one that compiles and warms up; a CPU batch predicted to take over BLOCK_SECONDS a block
    is skipped."""
    from softarm.config import load_config
    from softarm.sim.batch import arm_batch
    from softarm.sim.physics import Simulator
    from softarm.sim.runtime import init_taichi

    init_taichi(arch)
    config = load_config()
    per_arm_frame = config.integration.substeps * 164
    rates: dict[int, float] = {}
    for arms in arms_list:
        if rates and arch == "cpu" and arms * frames * per_arm_frame / list(rates.values())[-1] > BLOCK_SECONDS:
            break
        sim = Simulator.from_config(config, arm_batch(config, seeds=range(arms)), block_frames=frames)
        sim.step_block(frames)
        best = min(timed(lambda: sim.step_block(frames)) for _ in range(3))
        rates[arms] = arms * frames * per_arm_frame / best
        sim.close()
    return rates


def timed(action) -> float:
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def child(arch: str, arms: list[int], frames: int) -> dict[int, float]:
    run = subprocess.run([sys.executable, "-m", "bench.gpu_physics", arch, str(frames), *map(str, arms)],
                         capture_output=True, text=True, cwd=Path(__file__).parents[1])
    if run.returncode != 0:
        print(f"bench.gpu: the {arch} scaling run failed: {run.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
        return {}
    return {int(k): v for k, v in json.loads(run.stdout.splitlines()[-1]).items()}


def scaling_rows(cuda: bool, quick: bool) -> list[dict]:
    """Spring updates per second at each batch size: the GPU, every CPU core, and the C loop on one core."""
    from bench.c_reference import find_compiler
    from bench.run import c_reference_rate
    from softarm.config import load_config

    arms = list(GPU_ARMS[:4] if quick else GPU_ARMS)
    frames = 10 if quick else 20
    gpu = child("gpu", arms, frames) if cuda else {}
    cpu = child("cpu", arms, frames)
    c_rate = c_reference_rate(load_config(), 300 if quick else 2000) if find_compiler() else None
    rows = []
    for n in arms:
        notes = [] if n in cpu else [f"CPU not timed: one {frames}-frame block would take over {BLOCK_SECONDS:g} s"]
        best = gpu.get(n) or cpu.get(n)
        if c_rate is not None and best:
            notes.append(f"{best / c_rate:,.1f}x the C loop on one core")
        note = "; ".join(notes)
        rows.append({"section": "physics: spring updates per second",
                     "name": f"{n:,} arm{'s' if n > 1 else ''}, {frames}-frame blocks",
                     "gpu": gpu.get(n), "cpu": cpu.get(n), "unit": "spring updates/s", "note": note})
    if c_rate is not None:
        rows.append({"section": "physics: spring updates per second", "name": "hand-written C loop, one core",
                     "cpu": c_rate, "unit": "spring updates/s", "note": "bench/physics_reference.c, -O3"})
    return rows


def equality_rows(cuda: bool, quick: bool) -> list[dict]:
    """The same run on the GPU and on the CPU: byte-identical files, or the largest node difference."""
    if not cuda:
        return [{"section": "physics: GPU against CPU", "name": "recordings compared", "unit": "",
                 "note": "needs a CUDA GPU"}]
    from softarm.record.reader import read_recording

    rows = []
    with tempfile.TemporaryDirectory() as folder:
        world = Path(folder) / "world.toml"
        world.write_text("".join("[[disturbances]]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in d.items())
                                 for d in WORLD))
        for name, extra in (("the default run", []), ("every kind of disturbance", ["--config", str(world)])):
            duration = "10" if quick or extra else "100"
            paths = {}
            for arch in ("cpu", "gpu"):
                paths[arch] = Path(folder) / f"{arch}.mcap"
                subprocess.run([SOFTARM, "sim", "--duration", duration, "--arch", arch, "--out", str(paths[arch]),
                                "-q", "--force", *extra], check=True)
            same = paths["cpu"].read_bytes() == paths["gpu"].read_bytes()
            a, b = (read_recording(paths[arch]) for arch in ("cpu", "gpu"))
            gap = float(np.abs(a.positions - b.positions).max())
            frames = int((a.frames != b.frames).any(axis=(1, 2)).sum())
            rows.append({"section": "physics: GPU against CPU", "name": f"{name}, {duration} s",
                         "gpu": "identical files" if same else f"largest node difference {gap:.3g} m",
                         "unit": "", "note": f"{frames} frames differ in a pixel"})
    return rows


def recording_rows(cuda: bool, quick: bool) -> list[dict]:
    """`softarm sim --arms N --duration 10`, files written, start-up included: arm-seconds recorded per second."""
    duration = 2.0 if quick else 10.0
    rows = []
    for arch, arms in (("gpu", 256 if quick else 4096), ("cpu", 64 if quick else cpu_arms())):
        if arch == "gpu" and not cuda:
            continue
        seconds, size, files, peak = sim_run(arch, arms, duration)
        rows.append({"section": "recording: softarm sim, files written", "unit": "arm-s recorded per s",
                     "name": f"{arms:,} arms x {duration:g} s on the {arch.upper()}",
                     arch: arms * duration / seconds,
                     "note": f"{seconds:.1f} s wall, {files} files, {size / 1e6:,.0f} MB, "
                             f"peak {peak / 1e9:.1f} GB host"})
    return rows


def cpu_arms() -> int:
    """The CPU's batch: as many arms as a 16-core machine records in seconds, fewer on a small one."""
    import os

    return 4096 if len(os.sched_getaffinity(0)) >= 8 else 256


def sim_run(arch: str, arms: int, duration: float) -> tuple[float, int, int, int]:
    """(wall seconds, bytes written, files, peak resident bytes of the command and its writers) of one
    `softarm sim`, after a run of two frames that compiles the batch's kernels (Taichi's cache has them)."""
    with tempfile.TemporaryDirectory() as folder:
        args = [SOFTARM, "sim", "--arms", str(arms), "--arch", arch, "--out", "b.mcap", "-q", "--force"]
        subprocess.run([*args, "--duration", "0.02"], cwd=folder, check=True)
        start = time.perf_counter()
        peak = peak_memory([*args, "--duration", str(duration)], folder)
        seconds = time.perf_counter() - start
        written = list(Path(folder).glob("*.mcap"))
        return seconds, sum(p.stat().st_size for p in written), len(written), peak


def peak_memory(args: list[str], cwd: str) -> int:
    """Run a command to its end; the largest sum of resident memory over it and its child processes, sampled
    every 50 ms."""
    import psutil

    process = psutil.Popen(args, cwd=cwd)
    peak = 0
    while process.poll() is None:
        try:
            tree = [process, *process.children(recursive=True)]
            peak = max(peak, sum(p.memory_info().rss for p in tree if p.is_running()))
        except psutil.Error:
            pass
        time.sleep(0.05)
    if process.returncode != 0:
        raise subprocess.CalledProcessError(process.returncode, args)
    return peak


if __name__ == "__main__":  # the child process of one backend's scaling rows
    print(json.dumps(scaling(sys.argv[1], [int(a) for a in sys.argv[3:]], int(sys.argv[2]))))
