"""`softarm sim` through the real command: outputs, bad input, interruption, determinism."""

import signal
import subprocess
import time

import numpy as np
import pytest

from softarm.record.reader import read_recording
from tests.helpers.cli import SOFTARM, assert_one_line_error, files_under, softarm


@pytest.mark.slow
def test_short_run_writes_a_readable_recording_and_a_summary(tmp_path):
    result = softarm("sim", "--duration", "0.5", "--out", "run.mcap", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "wrote 50 frames" in result.stdout and "real time" in result.stdout
    rec = read_recording(tmp_path / "run.mcap")
    assert rec.frames.shape == (50, 84, 52) and rec.stretch.shape == (50, 4)
    assert rec.complete and not rec.truncated
    np.testing.assert_allclose(rec.times, np.arange(50) * 0.01)
    assert files_under(tmp_path) == [tmp_path / "run.mcap"]


@pytest.mark.slow
def test_default_output_goes_under_recordings_named_by_seed(tmp_path):
    result = softarm("sim", "--duration", "0.05", "--seed", "3", "--quiet", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout == "" and result.stderr == ""
    assert (tmp_path / "recordings" / "seed3.mcap").exists()


@pytest.mark.slow
def test_same_config_and_seed_give_byte_identical_files(tmp_path):
    for name in ("a.mcap", "b.mcap"):
        assert softarm("sim", "--duration", "1", "--seed", "2", "--out", name, "-q", cwd=tmp_path).returncode == 0
    assert (tmp_path / "a.mcap").read_bytes() == (tmp_path / "b.mcap").read_bytes()


@pytest.mark.slow
def test_a_batch_written_by_several_writers_is_byte_identical_run_after_run(tmp_path):
    for folder in ("one", "two"):
        result = softarm("sim", "--duration", "3", "--arms", "3", "--out", f"{folder}/b.mcap", "-q", cwd=tmp_path)
        assert result.returncode == 0, result.stderr
    for arm in range(3):
        assert ((tmp_path / "one" / f"b_arm{arm}.mcap").read_bytes()
                == (tmp_path / "two" / f"b_arm{arm}.mcap").read_bytes())


@pytest.mark.slow
def test_batch_arms_write_one_file_each_equal_to_their_single_seed_runs(tmp_path):
    assert softarm("sim", "--duration", "0.3", "--arms", "2", "--seed", "5", "--out", "b.mcap", "-q",
                   cwd=tmp_path).returncode == 0
    assert softarm("sim", "--duration", "0.3", "--seed", "6", "--out", "single.mcap", "-q",
                   cwd=tmp_path).returncode == 0
    arm0, arm1 = read_recording(tmp_path / "b_arm0.mcap"), read_recording(tmp_path / "b_arm1.mcap")
    single = read_recording(tmp_path / "single.mcap")
    assert arm1.model["seed"] == 6 and arm0.model["seed"] == 5
    np.testing.assert_array_equal(arm1.positions, single.positions)
    np.testing.assert_array_equal(arm1.frames, single.frames)
    assert not np.array_equal(arm0.positions, arm1.positions)


def test_version_and_help_with_an_example(tmp_path):
    assert softarm("--version", cwd=tmp_path).stdout.startswith("softarm ")
    help_text = softarm("sim", "--help", cwd=tmp_path).stdout
    assert "Example: softarm sim" in help_text and "--substeps" in help_text


BAD_CONFIGS = {
    "malformed TOML": ("[body\nrows = 3", ["not valid TOML"]),
    "unknown key": ("[springs]\nstifness = 10.0", ["springs.stifness", "did you mean 'springs.stiffness'"]),
    "wrong type": ("[springs]\nstiffness = 'stiff'", ["springs.stiffness", "must be a number"]),
    "negative mass": ("[body]\nnode_mass = -0.01", ["body.node_mass", "> 0"]),
    "zero nodes": ("[body]\nrows = 0", ["body.rows", "at least 2"]),
    "zero stiffness": ("[springs]\nstiffness = 0", ["springs.stiffness", "> 0"]),
    "zero frame step": ("[integration]\nframe_dt = 0.0", ["integration.frame_dt", "> 0"]),
    "sensor on a missing node": ("[sensors]\npairs = [[3, 27], [5, 999]]", ["sensors.pairs[1]", "node 999", "0..56"]),
    "outline on a missing node": ("[camera]\noutline = [0, 54, 56, 80]", ["camera.outline", "node 80"]),
    "unstable step": ("[integration]\nsubsteps = 5", ["integration.substeps", "unstable", ">= 11"]),
    "unknown integrator": ("[integration]\nintegrator = 'rk4'", ["integration.integrator", "symplectic_euler"]),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(BAD_CONFIGS))
def test_bad_config_is_refused_in_one_line_with_no_file_left(tmp_path, case):
    text, words = BAD_CONFIGS[case]
    (tmp_path / "bad.toml").write_text(text)
    result = softarm("sim", "--config", "bad.toml", "--duration", "0.1", "--out", "x.mcap", cwd=tmp_path)
    assert_one_line_error(result, *words)
    assert files_under(tmp_path) == []


BAD_OPTIONS = {
    "missing config file": (["--config", "nope.toml"], ["nope.toml", "not found"]),
    "zero duration": (["--duration", "0"], ["run.duration", "> 0"]),
    "negative duration": (["--duration", "-3"], ["run.duration"]),
    "zero arms": (["--arms", "0"], ["run.arms"]),
    "unknown arch": (["--arch", "tpu"], ["tpu", "cpu"]),
    "blow-up mid-run": (["--amplitude", "0.6", "--duration", "3"], ["blew up at t =", "node", "substeps"]),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(BAD_OPTIONS))
def test_bad_option_is_refused_in_one_line_with_no_file_left(tmp_path, case):
    args, words = BAD_OPTIONS[case]
    result = softarm("sim", "--duration", "0.2", *args, "--out", "x.mcap", cwd=tmp_path)
    assert_one_line_error(result, *words)
    assert files_under(tmp_path) == []


@pytest.mark.slow
def test_existing_output_is_kept_unless_forced(tmp_path):
    (tmp_path / "x.mcap").write_text("precious")
    assert_one_line_error(softarm("sim", "--duration", "0.1", "--out", "x.mcap", cwd=tmp_path), "exists", "--force")
    assert (tmp_path / "x.mcap").read_text() == "precious"
    assert softarm("sim", "--duration", "0.1", "--out", "x.mcap", "--force", "-q", cwd=tmp_path).returncode == 0
    assert read_recording(tmp_path / "x.mcap").frames.shape[0] == 10


def test_output_whose_parent_is_a_file_is_refused(tmp_path):
    (tmp_path / "afile").write_text("")
    result = softarm("sim", "--duration", "0.1", "--out", "afile/x.mcap", cwd=tmp_path)
    assert_one_line_error(result, "afile", "not a folder")


@pytest.mark.slow
def test_ctrl_c_keeps_every_frame_so_far_in_a_closed_file(tmp_path):
    proc = subprocess.Popen([SOFTARM, "sim", "--duration", "100", "--out", "run.mcap", "--quiet"], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    part = tmp_path / "run.mcap.part"
    deadline = time.time() + 60
    while (not part.exists() or part.stat().st_size < 2_000_000) and time.time() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and "complete = false" in stderr
    rec = read_recording(tmp_path / "run.mcap")
    assert not rec.complete and not rec.truncated
    assert 0 < len(rec.times) < 10000
    np.testing.assert_allclose(rec.times, np.arange(len(rec.times)) * 0.01)
    assert not part.exists()


@pytest.mark.slow
def test_arch_gpu_runs_on_a_gpu_or_says_in_one_line_that_there_is_none(tmp_path):
    result = softarm("sim", "--arch", "gpu", "--duration", "0.1", "--out", "g.mcap", "-q", cwd=tmp_path)
    if result.returncode == 0:  # a machine with a CUDA GPU
        assert read_recording(tmp_path / "g.mcap").frames.shape[0] == 10
    else:  # never a crash (Taichi's own GPU probe segfaults on some machines)
        assert_one_line_error(result, "--arch gpu", "no CUDA GPU", "--arch cpu or auto")
        assert files_under(tmp_path) == []


@pytest.mark.slow
def test_arch_auto_falls_back_to_the_cpu(tmp_path):
    result = softarm("sim", "--arch", "auto", "--duration", "0.1", "--out", "a.mcap", "-q", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert read_recording(tmp_path / "a.mcap").frames.shape[0] == 10
