"""The device vector env as an `rsl-rl` `VecEnv`, so rsl-rl's PPO (the one Isaac Lab trains with) learns from
thousands of arms whose tensors never leave the device (docs/guides/rl.md). Needs `pip install rsl-rl-lib`;
`softarm` never imports this module itself.

rsl-rl was chosen over skrl because its contract is the device env's own: torch tensors on the env's device in
and out, the ended arms reset within the step (SAME_STEP), time-outs told apart from terminations for bootstrapping
(`extras["time_outs"]`); skrl's Gymnasium wrapper converts through NumPy on the host. Each float observation key
becomes an observation group, flattened to (arms, features); `pixels` stays an image group, (arms, 1, H, W) float,
for rsl-rl's CNN models.
"""

from typing import Any, Optional

import torch
from gymnasium.vector import AutoresetMode, VectorEnv
from rsl_rl.env import VecEnv
from tensordict import TensorDict

IMAGES = ("pixels", "imagined_pixels")
OFFSET = 0.5  # the command an action of 0 stands for


class RslRlVecEnv(VecEnv):
    def __init__(self, env: VectorEnv, seed: Optional[int] = None):
        if env.metadata["autoreset_mode"] != AutoresetMode.SAME_STEP:
            raise ValueError("rsl-rl takes each step's observations after the resets: build the device vector env "
                             "with autoreset_mode=AutoresetMode.SAME_STEP")
        arms = env.unwrapped.arms
        if not isinstance(getattr(arms, "steps", None), torch.Tensor):
            raise ValueError("rsl-rl needs the env's tensors on a device: make it with device=\"cpu\" or \"cuda\"")
        self.env, self.arms = env, arms
        self.num_envs, self.num_actions = env.num_envs, arms.muscles.count
        self.max_episode_length = arms.episode_steps
        self.device = arms.device
        self.cfg = {"task": arms.task.name, "observations": list(env.single_observation_space.spaces)}
        obs, _ = env.reset(seed=seed)
        self._obs = self.groups(obs)

    @property
    def episode_length_buf(self) -> torch.Tensor:
        """Steps into each arm's episode: rsl-rl may randomise them to spread the episodes' ends."""
        return self.arms.steps

    @episode_length_buf.setter
    def episode_length_buf(self, steps: torch.Tensor) -> None:
        self.arms.steps.copy_(steps.clamp(0, self.max_episode_length - 1))

    def get_observations(self) -> TensorDict:
        return self._obs

    def step(self, actions: torch.Tensor) -> tuple[TensorDict, torch.Tensor, torch.Tensor, dict[str, Any]]:
        """One step of every arm with the commands 0.5 + actions (clipped to [0, 1] by the env): rsl-rl's Gaussian
        policy starts centred on 0, which puts an untrained policy in the middle of the commands' range."""
        obs, reward, terminated, truncated, info = self.env.step(actions + OFFSET)
        done = terminated | truncated
        log = {"/distance_mm": info["distance"].mean() * 1000.0}
        if bool(done.any()):
            log["/episode_success"] = terminated[done].float().mean()
        self._obs = self.groups(obs)
        return self._obs, reward, done.long(), {"time_outs": truncated, "log": log}

    def close(self) -> None:
        self.env.close()

    def groups(self, obs: dict[str, torch.Tensor]) -> TensorDict:
        """An observation dict of a softarm vector env (this one, or another of the same keys: an evaluation's) as
        rsl-rl's observation groups."""
        arms = len(next(iter(obs.values())))
        groups = {key: (value.float().unsqueeze(1) if key in IMAGES else value.float().reshape(arms, -1))
                  for key, value in obs.items()}
        return TensorDict(groups, batch_size=[arms], device=self.device)


def ppo_config(groups: list[str], steps_per_env: int = 24, hidden: tuple[int, ...] = (128, 128),
               learning_rate: float = 1e-3, entropy: float = 0.005, epochs: int = 5,
               mini_batches: int = 4) -> dict[str, Any]:
    """An `OnPolicyRunner` config for softarm's tasks: PPO with an MLP actor and critic reading the observation
    groups `groups`, normalised online, a Gaussian policy (the env clips its commands to [0, 1])."""
    model = {"class_name": "MLPModel", "hidden_dims": list(hidden), "activation": "elu", "obs_normalization": True}
    return {
        "num_steps_per_env": steps_per_env, "save_interval": 10**9, "obs_groups": {"actor": groups, "critic": groups},
        "actor": {**model, "distribution_cfg": {"class_name": "GaussianDistribution", "init_std": 0.3,
                                                "std_type": "scalar"}},
        "critic": model,
        "algorithm": {"class_name": "PPO", "learning_rate": learning_rate, "num_learning_epochs": epochs,
                      "num_mini_batches": mini_batches, "entropy_coef": entropy, "gamma": 0.99, "lam": 0.95,
                      "desired_kl": 0.01, "schedule": "adaptive", "clip_param": 0.2, "max_grad_norm": 1.0},
    }
