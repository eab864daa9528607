"""The device vector env against the NumPy vector env (the reference: same seeds, same episodes, same numbers within
float32 rounding, through autoresets and partial resets), Gymnasium's own vector wrappers and space checks, and the
promises the NumPy env keeps (bad actions refused, a closed env refuses, the imagined body alike)."""

import gymnasium
import numpy as np
import pytest
import torch
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.vector import AutoresetMode
from gymnasium.wrappers.vector import ArrayConversion, RecordEpisodeStatistics

import softarm.envs  # noqa: F401  (registers the ids)
from softarm.config import load_config
from softarm.envs.device_vector import DeviceVectorEnv
from softarm.envs.imagined import ImaginedBody
from softarm.envs.vector import SoftArmVectorEnv
from tests.envs.conftest import random_commands

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


QUICK = load_config(overrides={"control.episode": 0.3, "control.hold": 0.05, "control.workspace_samples": 16,
                               "control.tolerance": 0.02})  # 30 steps; Reach ends early now and then
EVERY = ("stretch", "activation", "target", "nodes", "pixels")


def as_numpy(value):
    return value.cpu().numpy() if isinstance(value, torch.Tensor) else np.asarray(value)


def assert_same(device_obs: dict, numpy_obs: dict) -> None:
    assert device_obs.keys() == numpy_obs.keys()
    for key, expected in numpy_obs.items():
        got = as_numpy(device_obs[key])
        assert got.dtype == expected.dtype and got.shape == expected.shape, key
        if key == "pixels":
            np.testing.assert_array_equal(got, expected)
        else:
            np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-6, err_msg=key)


@pytest.mark.parametrize("task", ["reach", "track", "hold"])
@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_the_device_env_on_the_cpu_equals_the_numpy_env_step_for_step(task, mode):
    arms, steps = 3, 75  # two autoresets and more of every arm
    reference = SoftArmVectorEnv(arms, task, QUICK, observe=EVERY, autoreset_mode=mode)
    device = DeviceVectorEnv(arms, task, QUICK, observe=EVERY, device="cpu", autoreset_mode=mode)
    expected, _ = reference.reset(seed=7)
    got, _ = device.reset(seed=7)
    assert_same(got, expected)
    ends = 0
    for t, u in enumerate(random_commands(steps, arms, seed=3)):
        if t == 40:  # a partial reset between the autoresets
            mask = np.array([True, False, True])
            expected, _ = reference.reset(options={"reset_mask": mask})
            got, _ = device.reset(options={"reset_mask": torch.as_tensor(mask)})
            assert_same(got, expected)
        expected, reward, terminated, truncated, info = reference.step(u)
        got, device_reward, device_terminated, device_truncated, device_info = device.step(torch.as_tensor(u))
        assert_same(got, expected)
        np.testing.assert_allclose(as_numpy(device_reward), reward, rtol=1e-6, atol=1e-6)
        np.testing.assert_array_equal(as_numpy(device_terminated), terminated)
        np.testing.assert_array_equal(as_numpy(device_truncated), truncated)
        np.testing.assert_allclose(as_numpy(device_info["distance"]), info["distance"], rtol=1e-9, atol=1e-12)
        if "final_obs" in info:
            ended = info["_final_obs"]
            np.testing.assert_array_equal(as_numpy(device_info["_final_obs"]), ended)
            for a in np.flatnonzero(ended):
                assert_same({k: v[a:a + 1] for k, v in device_info["final_obs"].items()},
                            {k: v[None] for k, v in info["final_obs"][a].items()})
        ends += int((terminated | truncated).sum())
    assert ends >= 2 * arms
    reference.close()
    device.close()


def test_make_vec_with_a_device_builds_the_device_env_and_gymnasiums_wrappers_check_it():
    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=4, device="cpu", config=QUICK)
    assert isinstance(envs.unwrapped, DeviceVectorEnv) and envs.unwrapped.device == torch.device("cpu")
    assert isinstance(gymnasium.make_vec("softarm/Reach-v0", num_envs=2, config=QUICK), SoftArmVectorEnv)
    wrapped = RecordEpisodeStatistics(ArrayConversion(envs, env_xp=torch, target_xp=np))
    obs, _ = wrapped.reset(seed=1)
    twin = gymnasium.make_vec("softarm/Reach-v0", num_envs=4, device="cpu", config=QUICK)
    again, _ = ArrayConversion(twin, env_xp=torch, target_xp=np).reset(seed=1)
    assert data_equivalence(obs, again)  # the same seed, the same start
    episodes = 0
    for _ in range(35):
        assert wrapped.observation_space.contains(obs)
        obs, reward, terminated, truncated, info = wrapped.step(wrapped.action_space.sample())
        assert reward.dtype == np.float32 and terminated.dtype == truncated.dtype == np.bool_
        episodes += int(info.get("_episode", np.zeros(4, bool)).sum())
    assert episodes >= 4  # every arm ended an episode, and the statistics wrapper saw it


def test_the_white_noise_comes_from_the_torch_generator_with_the_configured_spread():
    noisy = load_config(overrides={"control.workspace_samples": 16, "sensing.noise": 1e-4})
    env = DeviceVectorEnv(256, "reach", noisy, device="cpu")
    first, _ = env.reset(seed=0)
    second, _ = env.reset(seed=0)
    torch.testing.assert_close(first["stretch"], second["stretch"])  # seeded: repeatable
    ideal = DeviceVectorEnv(256, "reach", load_config(overrides={"control.workspace_samples": 16}), device="cpu")
    clean, _ = ideal.reset(seed=0)
    error = (first["stretch"] - clean["stretch"]).double() / 1000.0  # mm -> m
    assert abs(error.std().item() - 1e-4) < 0.05e-4 and abs(error.mean().item()) < 0.1e-4


@pytest.mark.parametrize("action, message", [(np.zeros((3, 4)), "shape"), (np.full((2, 4), np.nan), "NaN")])
def test_a_bad_action_is_refused_in_words_and_a_closed_env_refuses(action, message):
    env = DeviceVectorEnv(2, "reach", QUICK, device="cpu")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=message):
        env.step(action)
    env.close()
    with pytest.raises(gymnasium.error.ClosedEnvironmentError):
        env.step(np.zeros((2, 4)))


def test_the_imagined_body_on_the_device_env_equals_it_on_the_numpy_env(babble):
    _, checkpoint, _ = babble
    reference = ImaginedBody(SoftArmVectorEnv(3, "track", QUICK), checkpoint)
    device = ImaginedBody(DeviceVectorEnv(3, "track", QUICK, device="cpu"), checkpoint)
    expected, _ = reference.reset(seed=2)
    got, _ = device.reset(seed=2)
    for u in random_commands(40, 3, seed=5):  # through an autoreset
        for key in ("imagined", "confidence"):
            assert isinstance(got[key], torch.Tensor)
            np.testing.assert_allclose(as_numpy(got[key]), expected[key], atol=1e-5, err_msg=key)
        expected, *_ = reference.step(u)
        got, *_ = device.step(torch.as_tensor(u))
