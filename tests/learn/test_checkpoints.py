"""Checkpoints through the real command line: foreign or mismatched files refused in one line, and
Ctrl-C during training leaving a checkpoint that --resume finishes exactly."""

import json
import signal
import subprocess
import time

import pytest
import torch

from softarm.model.checkpoint import load_checkpoint
from tests.helpers.cli import SOFTARM, assert_one_line_error, softarm
from tests.helpers.tiny import TINY, tiny_toml


def tiny_config(folder):
    (folder / "tiny.toml").write_text(tiny_toml())
    return "tiny.toml"


@pytest.mark.slow
def test_checkpoint_of_another_model_shape_is_refused(recordings, tiny_checkpoint, tmp_path):
    state = load_checkpoint(tiny_checkpoint.checkpoint)
    state["config"]["train"]["latent"] = 12  # the weights are for 8 latent features
    torch.save(state, tmp_path / "other.pt")
    assert_one_line_error(softarm("replay", "other.pt", str(recordings / "s0.mcap"), cwd=tmp_path),
                          "do not fit")


@pytest.mark.slow
def test_a_surprise_model_of_an_earlier_softarm_is_refused_with_how_to_refit_it(recordings, tiny_checkpoint, tmp_path):
    state = load_checkpoint(tiny_checkpoint.checkpoint)
    old = state["surprise"]
    state["surprise"] = {key: old[key] for key in ("weights", "scale", "threshold", "felt", "command")}  # no kind
    torch.save(state, tmp_path / "earlier.pt")
    assert_one_line_error(softarm("replay", "earlier.pt", str(recordings / "s0.mcap"), cwd=tmp_path),
                          "--resume")


@pytest.mark.slow
def test_empty_checkpoint_is_refused(recordings, tmp_path):
    (tmp_path / "empty.pt").write_bytes(b"")
    assert_one_line_error(softarm("replay", "empty.pt", str(recordings / "s0.mcap"), cwd=tmp_path),
                          "empty.pt", "not a softarm checkpoint")


def test_resume_without_a_checkpoint_is_refused(recordings, tmp_path):
    result = softarm("train", str(recordings / "s0.mcap"), "--out", "none.pt", "--resume", cwd=tmp_path)
    assert_one_line_error(result, "--resume", "no checkpoint", "none.pt")


@pytest.mark.slow
def test_ctrl_c_during_training_keeps_a_valid_checkpoint_and_resume_ends_like_an_uninterrupted_run(
        recordings, tiny_checkpoint, tmp_path):
    config = tiny_config(tmp_path)
    source = str(recordings / "s0.mcap")
    proc = subprocess.Popen([SOFTARM, "train", source, "--config", config, "--out", "run.pt", "-q"],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while not (tmp_path / "run.pt").exists() and time.time() < deadline:  # the first epoch's checkpoint
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and "--resume" in stderr
    progress = load_checkpoint(tmp_path / "run.pt")["progress"]
    assert progress["phase"] == "ae" and progress["epoch"] < TINY["train.epochs_ae"]
    resumed = softarm("train", source, "--config", config, "--out", "run.pt", "--resume", "-q", cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    assert json.loads((tmp_path / "run.metrics.json").read_text()) == json.loads(json.dumps(tiny_checkpoint.metrics))
