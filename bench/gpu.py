"""The one benchmark for a CUDA machine: physics, recording and learning on the GPU against the same machine's CPU
(and the hand-written C loop on one core), measured in one run.

    python -m bench.gpu [--quick] [--sections physics,recording,learning,envs,pipeline|suite,controller]
                        [--out bench/results]

Prints every table and writes them to `bench/results/gpu.md` and `gpu.json`, with the machine, the date and the
softarm version. On a machine without CUDA it says so in one line and runs the CPU rows only. The sections:

- physics: spring updates per second from 1 to 65 536 arms on the GPU and on every CPU core, the C loop on one core
  beside them; and whether the GPU's recordings equal the CPU's (the default run, and a run with every kind of
  disturbance acting).
- recording: `softarm sim --arms N --duration 10`, files written, on the GPU and on the CPU: arm-seconds recorded
  per second.
- learning: optimisation steps per second of the autoencoder and the stream model, on the device and on the CPU.
- envs: env steps per second of the device vector env at 1 024, 16 384 and 65 536 arms, with state observations
  and with 84x52 pixels beside them, and of the physics kernel alone, on the GPU and (to 16 384 arms) the CPU.
- controller (not in the default; about ten minutes): `softarm babble` and `softarm train` of the body on the
  device, then rsl-rl's PPO on Reach (4 096 arms) with the stretch alone and with the imagined body, each until
  it reaches 95 % held-out success: the training's wall time to get there.
- pipeline (CUDA only): `softarm corpus DIR --arch gpu && softarm train DIR --device cuda` on defaults, its wall
  time and peak GPU and host memory; `suite` does the same, then writes the held-out suite and scores the model on
  it (the IoU to hold against the CPU-trained model's, on the results pages).

The default is sized to finish within about six minutes on an H200 with 16 cores beside it (`--quick`: a smoke test).
"""

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
from pathlib import Path
from typing import Callable

import softarm
from bench.gpu_envs import controller_rows, env_rows
from bench.gpu_learning import learning_rows, pipeline_rows
from bench.gpu_physics import equality_rows, recording_rows, scaling_rows

SECTIONS: dict[str, Callable[[bool, bool], list[dict]]] = {
    "physics": lambda cuda, quick: scaling_rows(cuda, quick) + equality_rows(cuda, quick),
    "recording": recording_rows,
    "learning": learning_rows,
    "envs": env_rows,
    "controller": controller_rows,
    "pipeline": pipeline_rows,
    "suite": lambda cuda, quick: pipeline_rows(cuda, quick, suite=True),  # the pipeline, then its suite scores
}
DEFAULT = "physics,recording,learning,envs,pipeline"  # about six minutes; `suite` (a few more) replaces `pipeline`


def machine() -> dict[str, str]:
    """The CPU, its cores, the GPU (if any) and the software that ran."""
    import torch

    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
               platform.processor()) if os.path.exists("/proc/cpuinfo") else platform.processor()
    gpu = torch.cuda.get_device_name(0) if torch.cuda.is_available() else "none"
    return {"cpu": f"{cpu}, {len(os.sched_getaffinity(0))} cores", "gpu": gpu, "python": platform.python_version(),
            "torch": torch.__version__, "softarm": softarm.__version__, "commit": commit(),
            "date": datetime.date.today().isoformat()}


def commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              cwd=Path(__file__).parent, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def markdown(rows: list[dict]) -> str:
    """One table per section: the figure on the GPU, on the CPU, and their ratio where both were measured."""
    out = []
    for section in dict.fromkeys(r["section"] for r in rows):
        out += [f"### {section}", "", "| measurement | GPU | CPU | GPU / CPU | unit | note |",
                "|---|---:|---:|---:|---|---|"]
        for r in (r for r in rows if r["section"] == section):
            gpu, cpu = r.get("gpu"), r.get("cpu")
            ratio = f"{gpu / cpu:,.1f}x" if isinstance(gpu, float) and isinstance(cpu, float) and cpu else ""
            out.append(f"| {r['name']} | {shown(gpu)} | {shown(cpu)} | {ratio} | {r['unit']} | {r.get('note', '')} |")
        out.append("")
    return "\n".join(out)


def shown(value: object) -> str:
    if isinstance(value, float):
        return f"{value:,.4g}"
    return "" if value is None else str(value)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer arms, frames and steps: a smoke test")
    ap.add_argument("--sections", default=DEFAULT, help=f"some of {','.join(SECTIONS)} [default: {DEFAULT}]")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    args = ap.parse_args()
    import torch

    cuda = torch.cuda.is_available()
    if not cuda:
        print("bench.gpu: torch sees no CUDA GPU here: running the CPU rows only", flush=True)
    about = machine()
    print(" | ".join(f"{k}: {v}" for k, v in about.items()), flush=True)
    rows: list[dict] = []
    for name in args.sections.split(","):
        if name not in SECTIONS:
            raise SystemExit(f"bench.gpu: no section {name!r}; give some of {','.join(SECTIONS)}")
        found = SECTIONS[name](cuda, args.quick)
        print(markdown(found), flush=True)
        rows += found
    args.out.mkdir(parents=True, exist_ok=True)
    head = (f"Measured {about['date']} with softarm {about['softarm']} (commit {about['commit']}) on "
            f"{about['cpu']}; GPU: {about['gpu']}; torch {about['torch']}, Python {about['python']}.")
    (args.out / "gpu.md").write_text(f"{head}\n\n{markdown(rows)}")
    (args.out / "gpu.json").write_text(json.dumps({"machine": about, "rows": rows}, indent=1))
    print(f"wrote {args.out / 'gpu.md'} and {args.out / 'gpu.json'}", file=sys.stderr)


if __name__ == "__main__":
    main()
