"""The control environments against Gymnasium's own checker, and the native vector env against the single env
stepped alike (spaces, shapes, seeding, the declared autoreset)."""

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from gymnasium.vector import AutoresetMode

import softarm.envs
from softarm.config import load_config
from softarm.envs.single import SoftArmEnv
from softarm.envs.vector import SoftArmVectorEnv

QUICK = {"control.episode": 0.2, "control.hold": 0.05, "control.workspace_samples": 16}  # 20 steps an episode
SHORT = load_config(overrides=QUICK)


@pytest.mark.slow
@pytest.mark.parametrize("task", sorted(softarm.envs.IDS))
def test_every_task_passes_gymnasiums_env_checker(task):
    env = gymnasium.make(softarm.envs.IDS[task], config=SHORT, observe=["stretch", "activation", "target", "nodes",
                                                                        "pixels"], render_mode="rgb_array")
    check_env(env.unwrapped, skip_render_check=False)
    env.reset(seed=1)
    image = env.render()
    assert (image.shape == (4 * 84, 4 * 52, 3) and image.dtype == np.uint8
            and len(np.unique(image.reshape(-1, 3), axis=0)) > 3)
    env.close()


@pytest.mark.slow
def test_make_vec_builds_the_native_vector_env_with_batched_spaces():
    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=3, config=SHORT)
    assert isinstance(envs, SoftArmVectorEnv)
    assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert envs.action_space.shape == (3, 4) and envs.single_action_space.shape == (4,)
    obs, info = envs.reset(seed=0)
    assert obs in envs.observation_space and obs["stretch"].shape == (3, 4) and obs["stretch"].dtype == np.float32
    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert reward.shape == terminated.shape == truncated.shape == (3,) and obs in envs.observation_space
    assert info["distance"].shape == (3,) and info["_distance"].all()
    control = SHORT.control  # the reward of README's task table, never above 0
    np.testing.assert_allclose(reward,
                               -info["distance"] / control.reward_scale - (info["distance"] >= control.tolerance))
    envs.close()


@pytest.mark.slow
@pytest.mark.parametrize("task", ["track", "hold"])  # hold: the shaking's phase and the push follow each episode
def test_each_arm_of_the_vector_env_runs_as_a_single_env_of_its_seed_through_autoresets(task):
    n, steps = 3, 45  # over two 20-step episodes: truncation, then NEXT_STEP's reset step, then a new episode
    config = load_config(overrides={**QUICK, "sensing.noise": 1e-4, "control.push_force": [1.0, 2.0]})
    envs = SoftArmVectorEnv(n, task, config)
    singles = [SoftArmEnv(task, config) for _ in range(n)]
    actions = np.random.default_rng(0).uniform(-0.2, 1.2, (steps, n, 4))  # some clipped
    got = [envs.reset(seed=10)[0]]
    expected = [[env.reset(seed=10 + a)[0] for a, env in enumerate(singles)]]
    resets, done = 0, [False] * n
    for t in range(steps):
        obs, reward, terminated, truncated, _ = envs.step(actions[t])
        got.append(obs)
        row = []
        for a, env in enumerate(singles):
            if done[a]:
                row.append(env.reset()[0])  # what NEXT_STEP promises: this step resets the arm, reward 0
                assert reward[a] == 0.0 and not terminated[a] and not truncated[a]
                done[a] = False
                resets += 1
                continue
            o, r, te, tr, _ = env.step(actions[t, a])
            done[a] = te or tr
            assert r == pytest.approx(reward[a], abs=1e-9) and (te, tr) == (terminated[a], truncated[a])
            row.append(o)
        expected.append(row)
    assert resets == 2 * n
    for t, (batch, row) in enumerate(zip(got, expected)):
        for key in batch:
            np.testing.assert_allclose(batch[key], np.stack([o[key] for o in row]), atol=1e-5, err_msg=f"{key} {t}")
    envs.close()
    for env in singles:
        env.close()


@pytest.mark.slow
def test_reset_with_the_same_seed_repeats_the_targets_and_readings():
    envs = SoftArmVectorEnv(4, "reach", load_config(overrides={**QUICK, "sensing.noise": 1e-4}))
    first = envs.reset(seed=3)[0]
    envs.step(np.full((4, 4), 0.5))
    again = envs.reset(seed=3)[0]
    assert len(np.unique(first["target"], axis=0)) > 1  # the arms draw their own targets
    for key in first:
        np.testing.assert_array_equal(first[key], again[key])
    envs.close()


@pytest.mark.slow
@pytest.mark.parametrize("action, message", [(np.full(3, 0.5), "shape"), (np.array([0.5, np.nan, 0, 0]), "NaN"),
                                             (np.array([0.5, np.inf, 0, 0]), "NaN or infinite")])
def test_a_bad_action_is_refused_in_words(action, message):
    env = SoftArmEnv("reach", SHORT)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=message):
        env.step(action)
    env.close()


@pytest.mark.slow
def test_out_of_range_commands_are_clipped_to_the_unit_interval():
    clipped, plain = SoftArmEnv("reach", SHORT), SoftArmEnv("reach", SHORT)
    for env in (clipped, plain):
        env.reset(seed=0)
    for _ in range(5):
        a = clipped.step(np.array([3.0, -2.0, 1.0, 0.0]))[0]
        b = plain.step(np.array([1.0, 0.0, 1.0, 0.0]))[0]
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    clipped.close()
    plain.close()


@pytest.mark.slow
def test_same_step_autoreset_returns_the_first_observation_and_keeps_the_last_in_info():
    same = SoftArmVectorEnv(2, "track", SHORT, autoreset_mode=AutoresetMode.SAME_STEP)
    next_step = SoftArmVectorEnv(2, "track", SHORT)
    assert same.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    for env in (same, next_step):
        env.reset(seed=4)
    actions = np.random.default_rng(1).uniform(0, 1, (20, 2, 4))
    for u in actions:  # 20 steps: the episode's end
        a, _, _, truncated, info = same.step(u)
        b, *_ = next_step.step(u)
    assert truncated.all() and info["_final_obs"].all()
    for arm in range(2):
        for key in b:
            np.testing.assert_array_equal(info["final_obs"][arm][key], b[key][arm])
    b, reward, *_ = next_step.step(actions[0])  # NEXT_STEP's reset step
    assert (reward == 0).all()
    for key in b:
        np.testing.assert_array_equal(a[key], b[key])


@pytest.mark.slow
@pytest.mark.parametrize("vector", [False, True], ids=["Env", "VectorEnv"])
def test_a_closed_env_refuses_every_call_instead_of_crashing(vector):
    from gymnasium.error import ClosedEnvironmentError

    env = SoftArmVectorEnv(2, config=SHORT) if vector else SoftArmEnv(config=SHORT, render_mode="rgb_array")
    env.reset(seed=0)
    env.close()
    env.close()  # twice is fine, as Gymnasium asks
    for call in (lambda: env.step(env.action_space.sample()), lambda: env.reset(seed=1), env.render):
        with pytest.raises(ClosedEnvironmentError, match="closed environment"):
            call()


@pytest.mark.slow
@pytest.mark.parametrize("mask", [[0, 1, 1], np.array([0, 2]), True, np.array([np.nan, 1.0, 0.0]),
                                  np.array([True, False])], ids=["ints", "indices", "scalar", "nan", "short"])
def test_a_reset_mask_that_is_not_one_boolean_per_arm_is_refused(mask):
    envs = SoftArmVectorEnv(3, config=SHORT)
    envs.reset(seed=0)
    with pytest.raises(ValueError, match=r"boolean array of shape \(3,\)"):
        envs.reset(options={"reset_mask": mask})
    envs.reset(options={"reset_mask": np.array([False, True, False])})  # the right one resets arm 1 only
    envs.close()


def test_more_arms_than_the_memory_holds_are_refused_before_any_is_made():
    with pytest.raises(ValueError, match="num_envs = 1000000000: give a whole number of arms from 1 to"):
        gymnasium.make_vec("softarm/Reach-v0", num_envs=10**9, config=SHORT)
    with pytest.raises(ValueError, match="num_envs = 0"):
        SoftArmVectorEnv(0, config=SHORT)
