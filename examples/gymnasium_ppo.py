"""A controller for the arm with an RL library: Stable-Baselines3's PPO on softarm's native Gymnasium vector env
(every arm stepped in one kernel), then a held-out evaluation of Reach's success, beside random commands.

    pip install -e ".[control]"                         # Stable-Baselines3
    python examples/gymnasium_ppo.py                    # 64 arms, 300 000 steps: about ten minutes on 2 cores
    python examples/gymnasium_ppo.py --arms 8 --steps 2048 --episodes 8   # a smoke test, seconds
"""

import argparse

import gymnasium
import numpy as np
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecNormalize

import softarm.envs  # noqa: F401  registers softarm/Reach-v0, Track-v0 and Hold-v0
from softarm.envs.sb3 import StableBaselinesVecEnv


def success_rate(policy, episodes: int, seed: int) -> float:
    """The share of `episodes` held-out Reach episodes (one per arm) that end with the tip held on target."""
    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=episodes)
    obs, _ = envs.reset(seed=seed)
    ended, succeeded = np.zeros(episodes, bool), np.zeros(episodes, bool)
    while not ended.all():
        obs, _, terminated, truncated, _ = envs.step(policy(obs))
        succeeded |= terminated & ~ended
        ended |= terminated | truncated
    envs.close()
    return float(succeeded.mean())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--arms", type=int, default=64, help="arms trained on side by side")
    parser.add_argument("--steps", type=int, default=300_000, help="environment steps of training, all arms together")
    parser.add_argument("--episodes", type=int, default=100, help="held-out evaluation episodes")
    args = parser.parse_args()

    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=args.arms)  # observe: stretch, activation, target
    train_env = VecNormalize(StableBaselinesVecEnv(envs), gamma=0.99)
    model = PPO("MultiInputPolicy", train_env, n_steps=64, batch_size=min(2048, 64 * args.arms), n_epochs=5,
                policy_kwargs={"net_arch": [128, 128]}, seed=0, verbose=0)
    model.learn(total_timesteps=args.steps)
    train_env.training = False

    def ppo(obs: dict) -> np.ndarray:
        action, _ = model.predict(train_env.normalize_obs(obs), deterministic=True)
        return action

    sampler = gymnasium.make_vec("softarm/Reach-v0", num_envs=args.episodes).action_space
    print(f"random commands: {success_rate(lambda obs: sampler.sample(), args.episodes, 10_000):.0%} success")
    print(f"PPO after {args.steps} steps: {success_rate(ppo, args.episodes, 10_000):.0%} success")
    envs.close()


if __name__ == "__main__":
    main()
