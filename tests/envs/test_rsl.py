"""rsl-rl's PPO on the device vector env through the adapter: the contract it reads (tensor groups on the env's
device, time-outs, episode lengths) and a short real training run that brings the tip nearer the target than the
random policy does on held-out episodes."""

import pytest
import torch
from gymnasium.vector import AutoresetMode
from rsl_rl.runners import OnPolicyRunner

from softarm.config import load_config
from softarm.envs.device_vector import DeviceVectorEnv
from softarm.envs.rsl import OFFSET, RslRlVecEnv, ppo_config

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


SHORT = load_config(overrides={"control.episode": 1.0, "control.workspace_samples": 16})  # 100 steps
STATE = ("stretch", "activation", "target")


def env_of(arms: int, mode: AutoresetMode = AutoresetMode.SAME_STEP) -> DeviceVectorEnv:
    return DeviceVectorEnv(arms, "reach", SHORT, observe=STATE, device="cpu", autoreset_mode=mode)


def test_the_adapter_hands_rsl_rl_tensor_groups_time_outs_and_episode_lengths():
    env = RslRlVecEnv(env_of(4), seed=0)
    obs = env.get_observations()
    assert set(obs.keys()) == set(STATE) and obs["stretch"].dtype == torch.float32 and obs.batch_size == (4,)
    assert env.num_actions == 4 and env.max_episode_length == 100 and env.device == torch.device("cpu")
    env.episode_length_buf = torch.full((4,), 99)
    obs, reward, done, extras = env.step(torch.zeros((4, 4)))  # the middle commands
    assert done.tolist() == [1, 1, 1, 1] and extras["time_outs"].all()  # the last step of each episode: time-outs
    assert (env.episode_length_buf == 0).all() and reward.shape == (4,) and "/episode_success" in extras["log"]
    with pytest.raises(ValueError, match="SAME_STEP"):
        RslRlVecEnv(env_of(2, AutoresetMode.NEXT_STEP))


def final_distance(policy, arms: int = 64) -> float:
    """Mean tip distance over the last half of one held-out episode of every arm (m)."""
    env = RslRlVecEnv(env_of(arms), seed=10_000)
    obs, distances = env.get_observations(), []
    for t in range(100):
        obs, *_ = env.step(policy(obs))
        if t >= 50:
            distances.append(env.arms.distance.clone())
    return float(torch.stack(distances).mean())


@pytest.mark.slow
def test_a_short_ppo_run_brings_the_tip_nearer_the_target_than_the_random_policy():
    torch.manual_seed(0)
    env = RslRlVecEnv(env_of(64), seed=0)
    runner = OnPolicyRunner(env, ppo_config(list(STATE)), log_dir=None, device="cpu")
    runner.learn(100)  # about 20 s on two cores
    policy = runner.get_inference_policy("cpu")
    generator = torch.Generator().manual_seed(1)
    trained = final_distance(lambda obs: policy(obs))
    random = final_distance(lambda obs: torch.rand((64, 4), generator=generator) - OFFSET)  # commands in [0, 1]
    assert trained < 0.7 * random, (trained, random)  # seen: 5.7 mm against 10.5 mm
