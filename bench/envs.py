"""Control environments' speed: env steps a second of the native `VectorEnv` against a Gymnasium
`SyncVectorEnv` of the same single envs, the device vector env on the CPU (torch tensors) and the physics kernel
alone, all in one run.

    python -m bench.envs [--arms 256] [--sync-arms 32] [--substeps 30] [--seconds 3]

Actions are random commands held for the run (the cost does not depend on them); each variant is timed after
one warm-up step, over at least `--seconds` of wall time. The SyncVectorEnv steps its single envs one after
another, so its env steps a second do not depend on how many it holds; it holds `--sync-arms` of them because
each single env compiles a kernel of its own (seconds each).
"""

import argparse
import time
from typing import Callable

import gymnasium
import numpy as np

import softarm.envs  # noqa: F401  (registers the ids)
from softarm.arm.muscles import build_muscles
from softarm.config import Config, load_config
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator
from softarm.sim.runtime import init_taichi

TASK = "softarm/Reach-v0"


def rate(step: Callable[[], None], arms: int, seconds: float) -> float:
    """Arm-steps a second of `step` (one step of `arms` arms)."""
    step()
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        step()
        count += 1
    return arms * count / (time.perf_counter() - start)


def vectorised(config: Config, arms: int, seconds: float, mode: str) -> float:
    """Env steps a second of `make_vec` in a vectorization mode: "vector_entry_point" (the native VectorEnv) or
    "sync" (a SyncVectorEnv of single envs)."""
    envs = gymnasium.make_vec(TASK, num_envs=arms, vectorization_mode=mode, config=config)
    envs.reset(seed=0)
    actions = np.random.default_rng(0).uniform(0, 1, envs.action_space.shape).astype(np.float32)
    out = rate(lambda: envs.step(actions), arms, seconds)
    envs.close()
    return out


def on_device(config: Config, arms: int, seconds: float) -> float:
    """Env steps a second of the device vector env with device="cpu", its actions a tensor."""
    import torch

    envs = gymnasium.make_vec(TASK, num_envs=arms, config=config, device="cpu")
    envs.reset(seed=0)
    actions = torch.rand(envs.action_space.shape, generator=torch.Generator().manual_seed(0))
    out = rate(lambda: envs.step(actions), arms, seconds)
    envs.close()
    return out


def physics(config: Config, arms: int, seconds: float) -> float:
    """The muscled kernel alone, one frame a launch, as the vector env launches it."""
    batch = arm_batch(config, seeds=range(arms))
    sim = Simulator.from_config(config, batch, block_frames=1, muscles=build_muscles(config, batch.body))
    sim.command(np.random.default_rng(0).uniform(0, 1, (arms, sim.muscles.count)))
    out = rate(lambda: sim.step_block(1), arms, seconds)
    sim.close()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", type=int, default=256)
    parser.add_argument("--sync-arms", type=int, default=32)
    parser.add_argument("--substeps", type=int, default=30)
    parser.add_argument("--seconds", type=float, default=3.0)
    args = parser.parse_args()
    init_taichi("cpu")
    config = load_config(overrides={"integration.substeps": args.substeps, "excitation.amplitude": 0.0})
    rows = [("native VectorEnv", vectorised(config, args.arms, args.seconds, "vector_entry_point")),
            (f"SyncVectorEnv of {args.sync_arms} single envs",
             vectorised(config, args.sync_arms, args.seconds, "sync")),
            ("device vector env on the CPU (torch tensors)", on_device(config, args.arms, args.seconds)),
            ("physics kernel alone", physics(config, args.arms, args.seconds))]
    vector = rows[0][1]
    print(f"| {args.arms} arms, {args.substeps} substeps | env steps/s | native VectorEnv's ratio |")
    print("|---|---:|---:|")
    for name, value in rows:
        print(f"| {name} | {value:,.0f} | {vector / value:.2f}x |")
    print(f"\nnative VectorEnv cost per arm-step: {rows[-1][1] / vector:.2f}x the physics kernel's")


if __name__ == "__main__":
    main()
