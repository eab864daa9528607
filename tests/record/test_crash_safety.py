"""A run cut off by a dead writer, a full disk or a signal keeps every frame that reached the disk, says
where, and ends within seconds; a run that cannot fit is refused in one line before any work."""

import errno
import os
import signal
import subprocess
import time
import warnings

import psutil
import pytest

from softarm.config import load_config
from softarm.files import part_path
from softarm.record.mcap_writer import McapWriter
from softarm.record.process import WriterFailed
from softarm.record.reader import TruncatedRecordingWarning, count_frames, read_recording
from softarm.sim.simulate import simulate
from tests.helpers.cli import SOFTARM, assert_one_line_error, files_under, softarm


def start(*args: str, cwd) -> subprocess.Popen:
    """`softarm sim ARGS` in a process group of its own, as a batch scheduler starts a job."""
    return subprocess.Popen([SOFTARM, "sim", *args], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)


def wait_for_chunks(folder, pattern: str, min_bytes: int = 1_500_000, seconds: float = 120) -> None:
    """Until every file of the run has a few chunks on disk."""
    deadline = time.time() + seconds
    while time.time() < deadline:
        files = list(folder.glob(pattern))
        if files and min(f.stat().st_size for f in files) > min_bytes:
            return
        time.sleep(0.05)
    raise AssertionError(f"no progress in {folder}")


def recovered(path) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncatedRecordingWarning)
        return len(read_recording(path, nodes=False).times)


@pytest.mark.slow
def test_a_killed_writer_keeps_every_complete_chunk_and_the_command_ends_in_seconds(tmp_path):
    proc = start("--arms", "2", "--duration", "300", "--out", "k.mcap", cwd=tmp_path)
    wait_for_chunks(tmp_path, "k_arm*.mcap.part")
    writers = psutil.Process(proc.pid).children()
    assert len(writers) == 2
    writers[1].send_signal(signal.SIGKILL)  # the writer of arm 1
    _, stderr = proc.communicate(timeout=30)
    message = assert_one_line_error(subprocess.CompletedProcess([], proc.returncode, "", stderr), "SIGKILL")
    closed, cut = tmp_path / "k_arm0.mcap", part_path(tmp_path / "k_arm1.mcap")
    assert closed.exists() and cut.exists() and not (tmp_path / "k_arm1.mcap").exists()
    rec = read_recording(closed, nodes=False)
    assert not rec.complete and len(rec.times) > 100 and f"{len(rec.times)} frames" in message
    assert recovered(cut) == count_frames(cut) > 100 and f"{count_frames(cut)} frames" in message


@pytest.mark.slow
def test_a_full_disk_keeps_what_was_written_and_says_so(tmp_path, monkeypatch):
    real = McapWriter.flush_chunk
    chunks = {"n": 0}

    def fill_up(self) -> None:  # the fourth chunk of a writer finds the disk full
        chunks["n"] += 1
        if chunks["n"] == 4:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(self)

    monkeypatch.setattr(McapWriter, "flush_chunk", fill_up)  # the writer processes fork with it
    started = time.time()
    with pytest.raises(WriterFailed) as failure:
        simulate(load_config(overrides={"run.duration": 20.0}), tmp_path / "full.mcap")
    assert time.time() - started < 30
    message = str(failure.value)
    assert "No space left on device" in message and "full.mcap.part" in message
    kept = part_path(tmp_path / "full.mcap")
    assert recovered(kept) == count_frames(kept) > 300 and f"{count_frames(kept)} frames" in message


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_signal_to_the_process_group_closes_every_file_with_every_frame(tmp_path, sig):
    proc = start("--arms", "2", "--duration", "1000", "--out", "s.mcap", cwd=tmp_path)
    wait_for_chunks(tmp_path, "s_arm*.mcap.part")
    os.killpg(proc.pid, sig)  # what `timeout`, a batch scheduler, a container stop or Ctrl-C sends
    _, stderr = proc.communicate(timeout=30)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and "complete = false" in stderr
    assert files_under(tmp_path) == [tmp_path / "s_arm0.mcap", tmp_path / "s_arm1.mcap"]
    frames = [read_recording(tmp_path / f"s_arm{i}.mcap", nodes=False) for i in range(2)]
    assert all(not r.complete and not r.truncated for r in frames)
    assert len(frames[0].times) == len(frames[1].times) > 100 and f"{len(frames[0].times)} frames" in stderr


@pytest.mark.slow
def test_writers_close_their_files_when_the_simulation_is_killed(tmp_path):
    proc = start("--arms", "2", "--duration", "1000", "--out", "p.mcap", cwd=tmp_path)
    wait_for_chunks(tmp_path, "p_arm*.mcap.part")
    proc.kill()
    proc.communicate(timeout=30)
    deadline = time.time() + 30
    while files_under(tmp_path) != [tmp_path / "p_arm0.mcap", tmp_path / "p_arm1.mcap"] and time.time() < deadline:
        time.sleep(0.1)
    for i in range(2):
        rec = read_recording(tmp_path / f"p_arm{i}.mcap", nodes=False)
        assert not rec.complete and len(rec.times) > 100


@pytest.mark.slow
@pytest.mark.parametrize("args, config, words", [
    (["--arms", "10000000"], "", ["10000000 arm(s)", "memory", "at most"]),
    (["--duration", "1e8"], "", ["frames per arm", "run.duration", "integration.frame_dt"]),
    ([], "[integration]\nframe_dt = 1e-9\nsubsteps = 1\n", ["frames per arm", "1e-09"]),
    ([], "[camera]\nwidth = 100000\nheight = 100000\n", ["100000 x 100000 camera", "memory", "pixels"]),
], ids=["huge batch", "absurd duration", "absurd frame step", "huge camera"])
def test_a_run_that_cannot_fit_is_refused_in_one_line_in_seconds(tmp_path, args, config, words):
    if config:
        (tmp_path / "c.toml").write_text(config)
        args = [*args, "--config", "c.toml"]
    started = time.time()
    result = softarm("sim", *args, "--out", "out/x.mcap", cwd=tmp_path)
    assert time.time() - started < 10
    assert_one_line_error(result, *words)
    assert result.returncode == 1 and not (tmp_path / "out").exists()


def test_a_run_bigger_than_the_free_disk_is_refused_before_any_work(tmp_path, monkeypatch):
    import shutil

    from softarm.errors import ConfigError

    usage = shutil.disk_usage(tmp_path)
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage._replace(free=50_000_000))
    with pytest.raises(ConfigError, match=r"would write about .* free: at most .* s of 1 arm"):
        simulate(load_config(overrides={"run.duration": 1000.0}), tmp_path / "out" / "x.mcap")
    assert not (tmp_path / "out").exists()


def test_a_writer_that_cannot_open_its_file_leaves_no_file_of_the_run(tmp_path, monkeypatch):
    from softarm.record import writer

    real = writer.RecordingWriter.__init__

    def refuse_arm_1(self, path, *args) -> None:
        if path.name.endswith("arm1.mcap"):
            raise OSError(errno.EACCES, os.strerror(errno.EACCES), str(path))
        real(self, path, *args)

    monkeypatch.setattr(writer.RecordingWriter, "__init__", refuse_arm_1)
    with pytest.raises(WriterFailed, match="Permission denied"):
        simulate(load_config(overrides={"run.duration": 1.0, "run.arms": 3}), tmp_path / "x.mcap")
    assert files_under(tmp_path) == []
