"""Episodes recorded by the control environments: the file re-simulates from its own metadata and commands (the
NumPy reference, not the env's kernel), `softarm train` learns from it with the activation as its command input,
and `softarm replay` shows it."""

import json

import gymnasium
import numpy as np
import pytest
from mcap.reader import make_reader

import softarm.envs  # noqa: F401
from softarm.arm.body import build_body
from softarm.arm.drive import Drive
from softarm.arm.muscles import Muscles
from softarm.arm.reference import simulate_reference
from softarm.config import config_from_dict, load_config
from softarm.disturbances import Push
from softarm.envs.record import RecordEpisodes
from softarm.record.reader import read_recording
from tests.helpers.cli import assert_one_line_error
from tests.helpers.cli import softarm as run_softarm

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def record(folder, task: str, seconds: float, episodes: int = 1) -> list:
    config = load_config(overrides={"control.episode": seconds, "control.workspace_samples": 16})
    env = RecordEpisodes(gymnasium.make(softarm.envs.IDS[task], config=config), folder)
    rng = np.random.default_rng(0)
    for episode in range(episodes):
        env.reset(seed=episode)
        command, done = rng.uniform(0, 1, 4), False
        while not done:
            if rng.random() < 0.05:  # babbling: a new random command now and then
                command = rng.uniform(0, 1, 4)
            done = any(env.step(command)[2:4])
    env.close()
    return sorted(folder.glob("*.mcap"))


def test_an_episode_re_simulates_from_its_metadata_and_commands(tmp_path):
    path, = record(tmp_path, "hold", 0.6)  # a shaken top and a push: the drive's phase and the push are recorded too
    rec = read_recording(path)
    model = rec.model
    config = config_from_dict(model["config"])
    m = model["muscles"]
    group = np.full(len(model["springs"]), -1, np.int32)
    for g, springs in enumerate(m["springs"]):
        group[springs] = g
    muscles = Muscles(tuple(m["names"]), group, np.array(m["max_contraction"]), m["time_constant"])
    commands = np.array([message for message in _commands(path)])
    drive = Drive(**{k: tuple(v) if isinstance(v, list) else v for k, v in model["excitation"].items()})
    push, = model["disturbances"]  # Hold pushes once an episode
    pushes = [Push(push["start"], push["end"], tuple(push["force"]), tuple(push["nodes"]))]
    again = simulate_reference(build_body(config), drive, np.array(model["initial"]["positions"]),
                               np.array(model["initial"]["velocities"]), model["frame_dt"], model["substeps"],
                               len(rec.times), pushes, muscles=muscles, commands=commands)
    assert rec.active[:, 0].any() and not rec.active[:, 0].all()  # /arm/disturbance labels the push
    assert len(rec.times) == 61 and rec.activation.shape == (61, 4)
    assert np.abs(rec.positions[-1] - rec.positions[0]).max() > 1e-3
    assert np.abs(again - rec.positions).max() < 1e-8  # the file rounds positions to 1e-9 m


def _commands(path):
    """The commands as a plain MCAP reader sees them."""
    with open(path, "rb") as f:
        for _, _channel, message in make_reader(f).iter_messages(topics=["/arm/activation"]):
            yield json.loads(message.data)["command"]


def test_episodes_train_with_the_activation_as_input_and_replay(babble, tmp_path):
    paths, checkpoint, trained = babble
    assert len(paths) == 2 and trained.returncode == 0, trained.stderr
    replayed = run_softarm("replay", str(checkpoint), str(paths[1]), "--mcap", str(tmp_path / "r.mcap"),
                           cwd=tmp_path, timeout=300)
    assert replayed.returncode == 0, replayed.stderr
    assert "IoU" in replayed.stdout and (tmp_path / "r.mcap").exists()


def test_babble_refuses_a_folder_that_holds_episodes_and_an_unknown_task(tmp_path):
    first = run_softarm("babble", str(tmp_path / "b"), "--episodes", "1", "--seconds", "1", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    before = sorted((tmp_path / "b").iterdir())
    assert_one_line_error(run_softarm("babble", str(tmp_path / "b"), "--episodes", "1", "--seconds", "1",
                                      cwd=tmp_path), "empty folder")
    assert sorted((tmp_path / "b").iterdir()) == before
    assert_one_line_error(run_softarm("babble", str(tmp_path / "c"), "--task", "fly", cwd=tmp_path), "fly", "reach")
