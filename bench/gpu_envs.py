"""bench.gpu's environment and controller rows: env steps per second of the device vector env (state observations,
and 84x52 pixels beside them) against the physics kernel alone, on the GPU and on the CPU; and the wall time of
rsl-rl's PPO to a Reach controller.

Taichi runs one backend per process, so each backend's env rows are measured in a child process of its own:

    python -m bench.gpu_envs cpu|gpu ARMS...
"""

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

ENV_ARMS = (1024, 16384, 65536)
CPU_ARMS = 16384  # the CPU's rows stop here: a step of 65 536 arms takes seconds on a few cores
STATE = ("stretch", "activation", "target")
SOFTARM = str(Path(sys.executable).with_name("softarm"))


def rate(step: Callable[[], None], arms: int, seconds: float, sync: Callable[[], None]) -> float:
    """Arm-steps a second of `step`, timed after two warm-up steps over at least `seconds`."""
    step()
    step()
    sync()
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        step()
        count += 1
    sync()
    return arms * count / (time.perf_counter() - start)


def env_rates(arch: str, arms_list: list[int], seconds: float) -> dict[int, dict[str, float]]:
    """In the child: for each batch, env steps a second with state observations, with pixels added, and of the
    muscled kernel alone (one frame a launch, as the env launches it)."""
    import torch

    from softarm.config import load_config
    from softarm.envs.device_vector import DeviceVectorEnv
    from softarm.model.device import synchronize
    from softarm.sim.runtime import init_taichi

    init_taichi(arch)
    device = torch.device("cuda" if arch == "gpu" else "cpu")
    config = load_config()
    out: dict[int, dict[str, float]] = {}
    for arms in arms_list:
        row = {}
        for name, observe in (("state", STATE), ("pixels", STATE + ("pixels",))):
            env = DeviceVectorEnv(arms, "reach", config, observe=observe, device=str(device))
            env.reset(seed=0)
            actions = torch.rand((arms, env.arms.muscles.count), generator=torch.Generator(device).manual_seed(0),
                                 device=device)
            row[name] = rate(lambda: env.step(actions), arms, seconds, lambda: synchronize(device))
            if name == "state":
                sim = env.arms.sim
                row["physics"] = rate(lambda: sim.step_on_device(1), arms, seconds, lambda: synchronize(device))
            env.close()
        out[arms] = row
    return out


def child(arch: str, arms: list[int], seconds: float) -> dict[int, dict[str, float]]:
    run = subprocess.run([sys.executable, "-m", "bench.gpu_envs", arch, str(seconds), *map(str, arms)],
                         capture_output=True, text=True, cwd=Path(__file__).parents[1])
    if run.returncode != 0:
        print(f"bench.gpu: the {arch} env run failed: {run.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
        return {}
    return {int(k): v for k, v in json.loads(run.stdout.splitlines()[-1]).items()}


def env_rows(cuda: bool, quick: bool) -> list[dict]:
    """Env steps a second at each batch: state observations, with pixels, and the physics alone."""
    arms = list(ENV_ARMS[:1] if quick else ENV_ARMS)
    seconds = 1.0 if quick else 3.0
    gpu = child("gpu", arms, seconds) if cuda else {}
    cpu = child("cpu", [n for n in arms if n <= CPU_ARMS], seconds)
    rows = []
    for n in arms:
        for key, what in (("state", "state observations"), ("pixels", "state and 84x52 pixels"),
                          ("physics", "physics kernel alone")):
            note = "" if n in cpu else f"CPU not timed above {CPU_ARMS:,} arms"
            rows.append({"section": "envs", "name": f"{n:,} arms, {what}", "unit": "env steps/s",
                         "gpu": gpu.get(n, {}).get(key), "cpu": cpu.get(n, {}).get(key), "note": note})
    return rows


def controller_rows(cuda: bool, quick: bool) -> list[dict]:
    """Wall time of rsl-rl's PPO to >= 95 % held-out success on Reach, with the stretch alone and with the imagined
    body of a stream model learned from babbling first (`softarm babble`, `softarm train`), on the device."""
    device = "cuda" if cuda else "cpu"
    episodes, seconds, minutes = (4, 4, 0.5) if quick else (24, 20, 4)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "babble.toml").write_text('[train]\ninputs = ["stretch", "activation"]\n')
        start = time.perf_counter()
        subprocess.run([SOFTARM, "babble", str(folder / "babble"), "--episodes", str(episodes), "--seconds",
                        str(seconds)], check=True, capture_output=True)
        subprocess.run([SOFTARM, "train", str(folder / "babble"), "--config", str(folder / "babble.toml"),
                        "--minutes", str(minutes), "--device", device, "--out", str(folder / "babble.pt")],
                       check=True, capture_output=True)
        rows.append({"section": "controller", "name": "babble and learn the body", "unit": "s",
                     "gpu" if cuda else "cpu": time.perf_counter() - start,
                     "note": f"{episodes} episodes of {seconds} s, train --minutes {minutes}"})
        for row in ("stretch", "imagined"):
            result = folder / f"{row}.json"
            arms = "4096" if cuda else "256"
            run = subprocess.run([sys.executable, "-m", "bench.controller", "--library", "rsl-rl", "--device", device,
                                  "--rows", row, "--checkpoint", str(folder / "babble.pt"), "--arms", arms,
                                  "--minutes", "1" if quick else "5", "--json", str(result)],
                                 capture_output=True, text=True, cwd=Path(__file__).parents[1])
            if run.returncode != 0:
                print(f"bench.gpu: the {row} controller failed: {run.stderr.strip().splitlines()[-1:]}",
                      file=sys.stderr)
                continue
            r = json.loads(result.read_text())[row]
            rows.append({"section": "controller", "name": f"rsl-rl PPO on Reach, {row}", "unit": "s trained",
                         "gpu" if cuda else "cpu": r["seconds"],
                         "note": f"{r['success']:.0%} held-out success (100 episodes, target 95 %) after "
                                 f"{r['steps']:,} env steps"})
    return rows


if __name__ == "__main__":
    found = env_rates(sys.argv[1], [int(a) for a in sys.argv[3:]], float(sys.argv[2]))
    print(json.dumps({str(k): v for k, v in found.items()}))
