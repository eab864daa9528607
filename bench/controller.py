"""A reference controller on Reach: PPO trained on the vector env, for each observation set, against the random
policy (the floor) and a scripted feedforward (the static command of the workspace place nearest the target,
ramped over one second: it knows the arm's statics, not its state).

    python -m bench.controller [--minutes 10] [--arms 128] [--episodes 100]
                               [--rows random,scripted,privileged,stretch,imagined --checkpoint BABBLE.pt]
                               [--library sb3 | rsl-rl --device auto --target 0.95]

`--library sb3` (the default): Stable-Baselines3 on the NumPy vector env, on the CPU. `--library rsl-rl`: rsl-rl's
PPO on the device vector env (softarm.envs.rsl), every tensor on `--device`; it evaluates the policy every
`--every` iterations and stops as soon as it reaches `--target` success, reporting the training's wall time to
get there (evaluations not counted).

Each PPO row trains for `--minutes` of wall time (one torch thread per core), then runs deterministically on
`--episodes` held-out episodes (seeds 10 000 on, never trained on); success is Reach's own: the tip within
control.tolerance (5 mm) for control.hold (0.5 s). The `imagined` row adds the imagined body of `--checkpoint`
(a stream model trained on the env's own babbling: `softarm babble`) to the stretch row's observation. Needs
`pip install stable-baselines3` (sb3) or `pip install rsl-rl-lib` (rsl-rl).
"""

import argparse
import json
import time
from typing import Callable, Optional

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv

from softarm.config import load_config
from softarm.envs.device_vector import DeviceVectorEnv
from softarm.envs.imagined import ImaginedBody
from softarm.envs.vector import SoftArmVectorEnv
from softarm.envs.workspace import STREAM
from softarm.model.device import synchronize

OBSERVE = {"privileged": ("nodes", "activation", "target"), "stretch": ("stretch", "activation", "target"),
           "imagined": ("stretch", "activation", "target")}
HELD_OUT = 10_000


def vector_env(arms: int, observe: tuple, checkpoint: Optional[str], device: Optional[str] = None,
               autoreset_mode: AutoresetMode = AutoresetMode.NEXT_STEP) -> VectorEnv:
    """The NumPy vector env, or with `device` the device one; with `checkpoint`, the imagined body added."""
    env = (SoftArmVectorEnv(arms, "reach", load_config(), observe=observe) if device is None else
           DeviceVectorEnv(arms, "reach", load_config(), observe=observe, device=device,
                           autoreset_mode=autoreset_mode))
    return ImaginedBody(env, checkpoint) if checkpoint is not None else env


def host(value: object) -> np.ndarray:
    return value.cpu().numpy() if hasattr(value, "cpu") else np.asarray(value)


def evaluate(policy: Callable[[dict, VectorEnv], object], observe: tuple, episodes: int,
             checkpoint: Optional[str] = None, device: Optional[str] = None) -> dict:
    """Success rate and tip error at each held-out episode's end (its first episode per arm)."""
    env = vector_env(episodes, observe, checkpoint, device)
    obs, _ = env.reset(seed=HELD_OUT)
    ended = np.zeros(episodes, bool)
    success, error, steps = np.zeros(episodes, bool), np.zeros(episodes), np.zeros(episodes)
    for t in range(env.unwrapped.arms.episode_steps):
        obs, _, terminated, truncated, info = env.step(policy(obs, env))
        terminated, truncated, distance = host(terminated), host(truncated), host(info["distance"])
        now = (terminated | truncated) & ~ended
        success[now], error[now], steps[now] = terminated[now], distance[now], t + 1
        ended |= now
        if ended.all():
            break
    env.close()
    return {"success": float(success.mean()), "median_error_mm": float(np.median(error) * 1e3),
            "mean_steps": float(steps.mean())}


def scripted(obs: dict, env: VectorEnv) -> np.ndarray:
    arms = env.unwrapped.arms
    commands = np.random.default_rng(STREAM).uniform(0, 1, (len(arms.task.places), arms.muscles.count))
    nearest = np.argmin(np.linalg.norm(arms.task.places[None] - arms.target[:, None], axis=2), axis=1)
    return commands[nearest] * np.minimum(1.0, arms.steps / 100)[:, None]


def random_policy(obs: dict, env: VectorEnv) -> np.ndarray:
    return env.action_space.sample()


def train_ppo(observe: tuple, minutes: float, arms: int, checkpoint: Optional[str] = None, seed: int = 0):
    """PPO (MultiInputPolicy) on normalised observations and rewards, stopped after `minutes` of wall time."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecNormalize

    from softarm.envs.sb3 import StableBaselinesVecEnv

    class Budget(BaseCallback):
        def _on_training_start(self) -> None:
            self.start = time.perf_counter()

        def _on_step(self) -> bool:
            return time.perf_counter() - self.start < minutes * 60

    vec = VecNormalize(StableBaselinesVecEnv(vector_env(arms, observe, checkpoint)), gamma=0.99)
    vec.seed(seed)
    model = PPO("MultiInputPolicy", vec, n_steps=64, batch_size=2048, n_epochs=5, learning_rate=3e-4, gamma=0.99,
                gae_lambda=0.95, ent_coef=0.0, policy_kwargs={"net_arch": [128, 128]}, seed=seed, verbose=0)
    start = time.perf_counter()
    model.learn(total_timesteps=10**9, callback=Budget())
    trained = {"steps": int(model.num_timesteps), "seconds": time.perf_counter() - start}
    vec.training = False

    def policy(obs: dict, _env: Optional[VectorEnv]) -> np.ndarray:
        return model.predict(vec.normalize_obs(obs), deterministic=True)[0]

    return policy, trained


def train_rsl(observe: tuple, minutes: float, arms: int, checkpoint: Optional[str], device: str, target: float,
              episodes: int, every: int, seed: int = 0):
    """rsl-rl's PPO on the device env, evaluated every `every` iterations on the held-out episodes; stops at
    `target` success or after `minutes` of training."""
    import torch
    from rsl_rl.runners import OnPolicyRunner

    from softarm.envs.rsl import OFFSET, RslRlVecEnv, ppo_config

    torch.manual_seed(seed)
    env = RslRlVecEnv(vector_env(arms, observe, checkpoint, device, AutoresetMode.SAME_STEP), seed=seed)
    groups = [key for key in env.get_observations().keys() if key != "pixels"]
    runner = OnPolicyRunner(env, ppo_config(groups), log_dir=None, device=str(env.device))
    trained, iterations, result = 0.0, 0, {"success": 0.0}
    while trained < minutes * 60 and result["success"] < target:
        start = time.perf_counter()
        runner.learn(every)
        synchronize(env.device)
        trained += time.perf_counter() - start
        iterations += every
        policy = runner.get_inference_policy(str(env.device))

        def act(obs: dict, _env: VectorEnv) -> torch.Tensor:
            return policy(env.groups(obs)) + OFFSET  # the commands the adapter would give

        result = evaluate(act, observe, episodes, checkpoint, device)
        print(f"  {iterations} iterations, {trained:.0f} s: success {result['success']:.0%}", flush=True)
    steps = iterations * runner.cfg["num_steps_per_env"] * arms
    return {**result, "steps": steps, "seconds": trained, "device": str(env.device)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--arms", type=int, default=128)
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--rows", default="random,scripted,privileged,stretch")
    parser.add_argument("--checkpoint", default=None, help="the imagined row's checkpoint")
    parser.add_argument("--json", default=None)
    parser.add_argument("--library", choices=("sb3", "rsl-rl"), default="sb3")
    parser.add_argument("--device", default="auto", help="rsl-rl: auto | cpu | cuda")
    parser.add_argument("--target", type=float, default=0.95, help="rsl-rl: stop at this held-out success")
    parser.add_argument("--every", type=int, default=25, help="rsl-rl: iterations between evaluations")
    args = parser.parse_args()
    from softarm.model.device import torch_device
    from softarm.sim.runtime import init_taichi

    device = str(torch_device(args.device)) if args.library == "rsl-rl" else None
    init_taichi("gpu" if device == "cuda" else "cpu")
    results = {}
    for row in args.rows.split(","):
        if row in OBSERVE:
            checkpoint = args.checkpoint if row == "imagined" else None
            if args.library == "rsl-rl":
                results[row] = train_rsl(OBSERVE[row], args.minutes, args.arms, checkpoint, device, args.target,
                                         args.episodes, args.every)
            else:
                policy, trained = train_ppo(OBSERVE[row], args.minutes, args.arms, checkpoint)
                results[row] = {**evaluate(policy, OBSERVE[row], args.episodes, checkpoint), **trained}
        else:
            results[row] = evaluate({"random": random_policy, "scripted": scripted}[row], ("target",), args.episodes)
        print(row, json.dumps(results[row]), flush=True)
    print("| policy | observation | success (5 mm for 0.5 s) | median final tip error (mm) | trained |")
    print("|---|---|---:|---:|---|")
    for row, r in results.items():
        trained = f"{r['steps']:,} steps in {r['seconds'] / 60:.1f} min" if "steps" in r else "-"
        seen = ", ".join(OBSERVE.get(row, ("target",))) + (", imagined body" if row == "imagined" else "")
        print(f"| {row} | {seen} | {r['success']:.0%} | "
              f"{r['median_error_mm']:.1f} | {trained} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=2)


if __name__ == "__main__":
    main()
