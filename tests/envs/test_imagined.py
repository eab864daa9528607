"""The imagined body as an observation: batched over the arms of a vector env, equal to the checkpoint's own
batch answer on each arm's readings, restarted with each episode, and trainable by a real RL library."""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.envs.imagined import ImaginedBody
from softarm.envs.sb3 import StableBaselinesVecEnv
from softarm.envs.vector import SoftArmVectorEnv
from softarm.errors import CheckpointError
from softarm.imagine.trained import TrainedModel
from tests.envs.conftest import random_commands

QUICK = load_config(overrides={"control.episode": 0.3, "control.hold": 0.1,
                               "control.workspace_samples": 16})  # 30 steps


@pytest.mark.slow
def test_each_arms_imagination_equals_the_checkpoints_batch_answer_on_its_readings(babble):
    _, checkpoint, _ = babble
    env = ImaginedBody(SoftArmVectorEnv(3, "track", QUICK), checkpoint)
    imaginer = TrainedModel(checkpoint).imaginer
    arms = env.unwrapped.arms
    obs, _ = env.reset(seed=0)
    readings, imagined = [], []
    for u in random_commands(30, 3):  # one whole episode: the 30th step truncates
        readings.append(np.concatenate([arms.stretch, arms.activation], axis=1))
        imagined.append(obs["imagined"])
        obs, *_ = env.step(u)
    assert obs["imagined"].shape == (3, imaginer.latent_scaler.keep.sum()) and (obs["confidence"] > 0).all()
    for a in range(3):
        series = np.stack([r[a] for r in readings])
        answer = imaginer.latent.answer([imaginer.normalised(series)])[0]
        first = answer.targets[0] - imaginer.latent.lead  # the sample an answer reads last
        got = np.stack([i[a] for i in imagined])[first:first + len(answer.targets)]
        np.testing.assert_allclose(got, answer.latents, atol=1e-4)


@pytest.mark.slow
def test_an_arm_that_starts_a_new_episode_imagines_from_a_fresh_memory(babble):
    _, checkpoint, _ = babble
    env = ImaginedBody(SoftArmVectorEnv(2, "track", QUICK), checkpoint)
    env.reset(seed=0)
    for u in random_commands(30, 2):
        before, *_ = env.step(u)  # the 30th step ends the episode
    after, *_ = env.step(np.zeros((2, 4)))  # NEXT_STEP: the arms restart, hanging still, muscles relaxed
    # every Track episode starts from the same sample (no sensor noise), so a fresh memory imagines alike
    fresh, _ = ImaginedBody(SoftArmVectorEnv(2, "track", QUICK), checkpoint).reset(seed=7)
    np.testing.assert_allclose(after["imagined"], fresh["imagined"], atol=1e-6)
    assert np.abs(before["imagined"] - fresh["imagined"]).max() > 1e-2


@pytest.mark.slow
def test_a_checkpoint_that_reads_what_the_env_does_not_give_is_refused(babble):
    _, checkpoint, _ = babble
    three = load_config(overrides={"control.workspace_samples": 16, "sensing.pairs": [[3, 27], [5, 29], [27, 54]]})
    with pytest.raises(CheckpointError, match="stretch"):
        ImaginedBody(SoftArmVectorEnv(2, "reach", three), checkpoint)


@pytest.mark.slow
def test_stable_baselines3_ppo_trains_on_the_imagined_body_through_the_adapter(babble):
    from stable_baselines3 import PPO

    _, checkpoint, _ = babble
    env = StableBaselinesVecEnv(ImaginedBody(SoftArmVectorEnv(4, "reach", QUICK), checkpoint))
    model = PPO("MultiInputPolicy", env, n_steps=40, batch_size=80, n_epochs=1, seed=0)  # 40 steps cross a reset
    model.learn(total_timesteps=160)
    assert model.num_timesteps == 160
    action, _ = model.predict(env.reset(), deterministic=True)
    assert action.shape == (4, 4)
    env.close()
