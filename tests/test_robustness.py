"""Robustness through the real command line: foreign and damaged files, mismatches, unwritable outputs,
interruption of training, recordings cut short at arbitrary bytes.

The config and option cases of `softarm sim` are in test_sim_cli.py; these add the file and model
cases of `train` and `replay`. Every refusal: exit code != 0, one line naming the problem, no file.
"""

import json
import signal
import subprocess
import time
import warnings

import numpy as np
import pytest
import torch
from mcap.writer import Writer

from cli_helpers import SOFTARM, assert_one_line_error, softarm
from conftest import TINY
from softarm.checkpoint import load_checkpoint
from softarm.errors import RecordingError
from softarm.recording import TruncatedRecordingWarning, read_recording


def write_mcap(path, metadata=None):
    """A valid MCAP with one JSON channel and, optionally, one metadata record."""
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start()
        schema = writer.register_schema("x", "jsonschema", b"{}")
        channel = writer.register_channel("/x", "json", schema)
        if metadata:
            writer.add_metadata(*metadata)
        writer.add_message(channel, 0, b"{}", 0)
        writer.finish()


def tiny_config(folder):
    lines = ["[train]"] + [f"{key.split('.')[1]} = {value}" for key, value in TINY.items()]
    (folder / "tiny.toml").write_text("\n".join(lines) + "\n")
    return "tiny.toml"


def test_mcap_without_softarm_metadata_is_refused(tmp_path):
    write_mcap(tmp_path / "foreign.mcap")
    assert_one_line_error(softarm("train", "foreign.mcap", "--out", "x.pt", cwd=tmp_path),
                          "foreign.mcap", "not a softarm recording")
    assert not (tmp_path / "x.pt").exists()


def test_recording_of_a_newer_format_is_refused(tmp_path):
    write_mcap(tmp_path / "new.mcap", ("softarm", {"format": "softarm-recording/2", "model": "{}"}))
    assert_one_line_error(softarm("train", "new.mcap", "--out", "x.pt", cwd=tmp_path),
                          "softarm-recording/2", "upgrade softarm")


def test_recording_cut_before_its_metadata_is_refused(recordings, tmp_path):
    (tmp_path / "cut.mcap").write_bytes((recordings / "s0.mcap").read_bytes()[:200])
    assert_one_line_error(softarm("train", "cut.mcap", "--out", "x.pt", cwd=tmp_path), "cut short")


def test_checkpoint_of_another_model_shape_is_refused(recordings, tiny_checkpoint, tmp_path):
    state = load_checkpoint(tiny_checkpoint.checkpoint)
    state["config"]["train"]["latent"] = 12  # the weights are for 8 latent features
    torch.save(state, tmp_path / "other.pt")
    assert_one_line_error(softarm("replay", "other.pt", str(recordings / "s0.mcap"), cwd=tmp_path),
                          "do not fit")


def test_empty_checkpoint_is_refused(recordings, tmp_path):
    (tmp_path / "empty.pt").write_bytes(b"")
    assert_one_line_error(softarm("replay", "empty.pt", str(recordings / "s0.mcap"), cwd=tmp_path),
                          "empty.pt", "not a softarm checkpoint")


def test_recording_with_another_image_size_is_refused(tiny_checkpoint, tmp_path):
    (tmp_path / "narrow.toml").write_text("[camera]\nwidth = 40\norigin = [20.0, 3.0]\n")
    assert softarm("sim", "--config", "narrow.toml", "--duration", "0.2", "--out", "narrow.mcap", "-q",
                   cwd=tmp_path).returncode == 0
    result = softarm("replay", str(tiny_checkpoint.checkpoint), "narrow.mcap", "--png", "x.png", cwd=tmp_path)
    assert_one_line_error(result, "84x40 images", "trained on 84x52")
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("command", ["train", "replay"])
def test_output_whose_parent_is_a_file_is_refused(recordings, tiny_checkpoint, tmp_path, command):
    (tmp_path / "afile").write_text("")
    args = {"train": ["train", str(recordings / "s0.mcap"), "--out", "afile/x.pt"],
            "replay": ["replay", str(tiny_checkpoint.checkpoint), str(recordings / "s0.mcap"), "--mcap", "afile/x.mcap"]}
    assert_one_line_error(softarm(*args[command], cwd=tmp_path), "afile", "not a folder")


@pytest.mark.parametrize("command", ["train", "replay"])
def test_existing_output_is_refused_without_force(recordings, tiny_checkpoint, tmp_path, command):
    (tmp_path / "old").write_text("precious")
    args = {"train": ["train", str(recordings / "s0.mcap"), "--out", "old"],
            "replay": ["replay", str(tiny_checkpoint.checkpoint), str(recordings / "s0.mcap"), "--rrd", "old"]}
    assert_one_line_error(softarm(*args[command], cwd=tmp_path), "old", "exists", "--force")
    assert (tmp_path / "old").read_text() == "precious"


def test_resume_without_a_checkpoint_is_refused(recordings, tmp_path):
    result = softarm("train", str(recordings / "s0.mcap"), "--out", "none.pt", "--resume", cwd=tmp_path)
    assert_one_line_error(result, "--resume", "no checkpoint", "none.pt")


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


def test_a_recording_cut_at_any_byte_gives_back_every_complete_frame(recordings, tmp_path):
    data = (recordings / "s0.mcap").read_bytes()
    whole = read_recording(recordings / "s0.mcap")
    recovered = []
    for cut in np.linspace(len(data) // 50, len(data) - 1, 23).astype(int):
        (tmp_path / "cut.mcap").write_bytes(data[:cut])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                rec = read_recording(tmp_path / "cut.mcap")
            except RecordingError as e:
                assert "cut short" in str(e) or "no complete frame" in str(e)
                continue
        assert rec.truncated and not rec.complete
        assert any(issubclass(w.category, TruncatedRecordingWarning) and f"{len(rec.times)} complete frames"
                   in str(w.message) for w in caught)
        n = len(rec.times)
        np.testing.assert_array_equal(rec.frames, whole.frames[:n])
        np.testing.assert_array_equal(rec.stretch, whole.stretch[:n])
        recovered.append(n)
    assert recovered == sorted(recovered) and recovered[-1] == len(whole.times)


def test_replay_uses_a_truncated_recording_and_says_so(recordings, tiny_checkpoint, tmp_path):
    data = (recordings / "s0.mcap").read_bytes()
    (tmp_path / "cut.mcap").write_bytes(data[:int(len(data) * 0.7)])
    result = softarm("replay", str(tiny_checkpoint.checkpoint), "cut.mcap", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "truncated: recovered" in result.stderr and "imagined frames" in result.stdout
