"""The hostile but realistic cases users met, run through the command line as they ran them: every one gets one
line and an exit code that tells the truth, and no input is ever lost."""

import hashlib
import json
import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from softarm.record.reader import read_recording
from softarm.suite.families import SUITE_VERSION
from tests.helpers.cli import SOFTARM, assert_one_line_error, softarm
from tests.helpers.suites import mini_suite

TINY_TRAIN = ["--epochs-ae", "1", "--epochs-lstm", "1", "--latent", "8", "-q"]


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def rec(recordings, tmp_path) -> Path:
    """A recording of the user's own, in the folder the commands run in."""
    return Path(shutil.copy(recordings / "s1.mcap", tmp_path / "x.mcap"))


@pytest.fixture
def ckpt(tiny_checkpoint, tmp_path) -> Path:
    return Path(shutil.copy(tiny_checkpoint.checkpoint, tmp_path / "m.pt"))


@pytest.mark.slow
def test_outputs_never_replace_an_input(rec, ckpt, tmp_path):
    before = digest(rec)
    assert_one_line_error(softarm("replay", "m.pt", "x.mcap", "--mcap", "x.mcap", "--force", cwd=tmp_path),
                          "x.mcap", "is the input")
    assert_one_line_error(softarm("train", "x.mcap", "--out", "x.mcap", "--force", cwd=tmp_path), "is the input")
    os.link(rec, tmp_path / "hard.mcap")  # another name for the same file
    assert_one_line_error(softarm("replay", "m.pt", "x.mcap", "--png", "hard.mcap", "--force", cwd=tmp_path),
                          "hard.mcap", "is the input")
    assert_one_line_error(softarm("replay", "m.pt", "x.mcap", "--rrd", "./m.pt", "--force", cwd=tmp_path),
                          "is the input")
    assert digest(rec) == before and (tmp_path / "m.pt").stat().st_size > 0


@pytest.mark.slow
def test_evaluate_never_replaces_the_suites_own_files(rec, ckpt, tmp_path):
    suite = mini_suite(tmp_path / "suite", rec)
    manifest = (suite / "suite.json").read_text()
    assert_one_line_error(softarm("evaluate", "m.pt", "suite", "--json", "suite/suite.json", "--force", cwd=tmp_path),
                          "suite.json", "is the input")
    assert (suite / "suite.json").read_text() == manifest
    done = softarm("evaluate", "m.pt", "suite", "--json", "suite/scores.json", "-q", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert json.loads((suite / "scores.json").read_text())["suite"] == SUITE_VERSION


def test_two_outputs_on_one_file_are_refused(rec, tmp_path):
    assert_one_line_error(softarm("train", "x.mcap", "--out", "p.pt", "--rrd", "p.pt", cwd=tmp_path), "one file")
    assert not (tmp_path / "p.pt").exists()


def wait_for(path: Path, process: subprocess.Popen, seconds: float = 60) -> None:
    """Until `path` exists (the first run holds its output), failing if the process ends first."""
    end = time.monotonic() + seconds
    while not path.exists():
        assert process.poll() is None and time.monotonic() < end, "the first run ended before it held its output"
        time.sleep(0.02)


@pytest.mark.slow
@pytest.mark.parametrize("command", [["sim", "--duration", "30", "--out", "same.mcap", "--force", "-q"],
                                     ["train", "x.mcap", "--out", "same.pt", "--force", *TINY_TRAIN]])
def test_a_second_run_on_the_same_output_is_refused_and_the_first_finishes_whole(rec, tmp_path, command):
    output = tmp_path / command[command.index("--out") + 1]
    first = subprocess.Popen([SOFTARM, *command], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    wait_for(output.with_name(f".{output.name}.lock"), first)
    first.send_signal(signal.SIGSTOP)  # held still, so the second run surely overlaps it
    try:
        second = softarm(*command, cwd=tmp_path, timeout=300)
    finally:
        first.send_signal(signal.SIGCONT)
    _, first_err = first.communicate(timeout=300)
    assert first.returncode == 0, first_err
    assert_one_line_error(second, str(output.name), "another softarm run")
    if output.suffix == ".mcap":
        assert read_recording(output, nodes=False).complete
    else:
        from softarm.imagine.trained import TrainedModel

        TrainedModel(output)
    assert not list(tmp_path.glob(".*.lock")) and not list(tmp_path.glob("*.part"))


@pytest.mark.slow
def test_damaged_checkpoints_and_corpus_manifests_get_one_line(rec, tmp_path):
    # random bytes, opening as a pickle of protocol 83: torch warns of that before it fails, and the user still
    # gets one line
    (tmp_path / "random.pt").write_bytes(b"\x80\x53" + np.random.default_rng(0).bytes(4998))
    assert_one_line_error(softarm("replay", "random.pt", "x.mcap", cwd=tmp_path), "random.pt",
                          "not a softarm checkpoint")
    suite = mini_suite(tmp_path / "suite", rec)
    assert_one_line_error(softarm("evaluate", "random.pt", str(suite), cwd=tmp_path), "random.pt")
    corpus = tmp_path / "corpus"
    corpus.mkdir()
    shutil.copy(rec, corpus / "a.mcap")
    for text in ("{not json", "[1, 2]"):
        (corpus / "corpus.json").write_text(text)
        assert_one_line_error(softarm("train", "corpus", cwd=tmp_path), "corpus.json", "not a corpus manifest")


@pytest.mark.slow
def test_a_corpus_is_one_only_with_its_manifest_and_force_leaves_nothing_of_the_old_one(tmp_path):
    done = softarm("corpus", "c", "--preset", "paper", "--arms", "3", "--duration", "0.3", "-q", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert len(list((tmp_path / "c").glob("*.mcap"))) == 3
    (tmp_path / "c" / "corpus.json").unlink()  # as an interrupted run leaves it: the plan, no manifest
    (tmp_path / "c" / ".corpus-incomplete.json").write_text(json.dumps(
        {"preset": "paper", "recordings": ["paper_arm0.mcap", "paper_arm1.mcap", "paper_arm2.mcap"]}))
    assert_one_line_error(softarm("train", "c", cwd=tmp_path), "incomplete corpus", "softarm corpus")
    again = softarm("corpus", "c", "--preset", "paper", "--arms", "1", "--duration", "0.3", "-q", cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert sorted(p.name for p in (tmp_path / "c").glob("*.mcap")) == ["paper.mcap"]
    assert_one_line_error(softarm("corpus", "d", "--arms", "2", cwd=tmp_path), "--arms 2", "19 group")


@pytest.mark.slow
def test_an_interrupted_forced_training_leaves_no_metrics_of_the_old_run(rec, tmp_path):
    from softarm.config import load_config
    from softarm.learn.training import train
    from tests.helpers.tiny import TINY

    first = train([rec], load_config(overrides={**TINY, "train.epochs_ae": 1, "train.epochs_lstm": 1}),
                  tmp_path / "m.pt")
    assert first.metrics_path.exists()
    calls = iter(range(10**6))  # asked once per recording read, then after every step: 11 steps an epoch here
    stopped = train([rec], load_config(overrides=TINY), tmp_path / "m.pt", force=True, stop=lambda: next(calls) > 14)
    assert not stopped.complete and stopped.saved and not first.metrics_path.exists()


@pytest.mark.slow
def test_a_stopped_training_leaves_only_what_it_was_asked_for(recordings, tmp_path):
    folder = tmp_path / "corpus"
    folder.mkdir()
    for name in ("s0.mcap", "s1.mcap"):
        shutil.copy(recordings / name, folder / name)
    run = subprocess.Popen([SOFTARM, "train", "corpus", "--out", "new/m.pt", *TINY_TRAIN], cwd=tmp_path,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(tmp_path / "new" / ".m.pt.lock", run)
    run.send_signal(signal.SIGTERM)
    _, err = run.communicate(timeout=120)
    assert run.returncode == 130 and len(err.strip().splitlines()) == 1 and "interrupted" in err, err
    left = [p.name for p in (tmp_path / "new").glob("*") if p.name != "m.pt"] if (tmp_path / "new").exists() else []
    assert left == [] and not list((tmp_path / "new").glob(".*"))  # the frames stay in memory: no cache on disk


def test_a_failed_training_leaves_no_folder_it_made(tmp_path):
    assert_one_line_error(softarm("train", "missing.mcap", "--out", "a/b/m.pt", cwd=tmp_path), "missing.mcap")
    assert not (tmp_path / "a").exists()


@pytest.mark.slow
def test_numbers_and_paths_are_checked_up_front(rec, ckpt, tmp_path):
    assert_one_line_error(softarm("train", "x.mcap", "--minutes", "nan", cwd=tmp_path), "--minutes", "finite")
    assert_one_line_error(softarm("sim", "--seed", str(2**70), cwd=tmp_path), "run.seed", "0..4294967295")
    (tmp_path / "folder.pt").mkdir()
    assert_one_line_error(softarm("train", "x.mcap", "--out", "folder.pt", cwd=tmp_path), "is a folder")
    assert_one_line_error(softarm("replay", "m.pt", "x.mcap", "--blind", "10:20", cwd=tmp_path), "lies outside")
    whole = softarm("replay", "m.pt", "x.mcap", "--blind", "2:1e9", cwd=tmp_path)  # blind from 2 s to the end
    assert whole.returncode == 0, whole.stderr
    assert not list(tmp_path.glob("recordings"))


@pytest.mark.slow
def test_resume_names_only_the_settings_asked_for_and_says_minutes_are_ignored(recordings, ckpt, tmp_path):
    shutil.copy(recordings / "s0.mcap", tmp_path / "x.mcap")  # what the tiny checkpoint was trained on
    again = softarm("train", "x.mcap", "--out", "m.pt", "--resume", "--minutes", "3", "-q", cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert "--minutes 3 is ignored with --resume" in again.stderr
    assert "train.epochs_ae" not in again.stderr  # the user set none of the saved run's settings now
    changed = softarm("train", "x.mcap", "--out", "m.pt", "--resume", "--seed", "4", "-q", cwd=tmp_path)
    assert "ignored: train.seed = 4" in changed.stderr


def writer_of(process: subprocess.Popen):
    """The writer process a `softarm sim` forked (not Python's resource tracker, which it may start too)."""
    import psutil

    def forked(child: psutil.Process, command: list[str]) -> bool:
        try:
            return child.cmdline() == command
        except psutil.Error:  # a short-lived child (a helper Taichi or Python runs at start-up) went in between
            return False

    end = time.monotonic() + 60
    while time.monotonic() < end:
        parent = psutil.Process(process.pid)
        writers = [c for c in parent.children() if forked(c, parent.cmdline())]
        if writers:
            return writers[0]
        time.sleep(0.05)
    raise AssertionError("no writer process started")


@pytest.mark.slow
def test_a_stuck_writer_ends_the_run_at_its_deadline_with_what_reached_the_disk(tmp_path):
    env = {**os.environ, "SOFTARM_WRITER_DEADLINE": "2"}
    run = subprocess.Popen([SOFTARM, "sim", "--duration", "3000", "--out", "s.mcap", "-q"], cwd=tmp_path, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    writer = writer_of(run)
    writer.suspend()  # alive, but stuck: as a hung disk leaves it
    try:
        _, err = run.communicate(timeout=60)
    finally:
        if writer.is_running():
            writer.kill()
    assert run.returncode == 1 and "answered nothing for 2 s" in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.slow
def test_a_second_ctrl_c_ends_the_run_at_once(tmp_path):
    run = subprocess.Popen([SOFTARM, "sim", "--duration", "3000", "--out", "s.mcap", "-q"], cwd=tmp_path,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    writer_of(run)  # the writers run: frames are on their way to the disk
    time.sleep(0.5)
    run.send_signal(signal.SIGINT)
    run.send_signal(signal.SIGINT)
    start = time.monotonic()
    _, err = run.communicate(timeout=60)
    assert run.returncode == 130 and len(err.strip().splitlines()) == 1 and "interrupted" in err, err
    assert time.monotonic() - start < 15
