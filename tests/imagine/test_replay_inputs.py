"""Replay on recordings it did not expect: another image size is refused, a truncated one is used
with a warning."""

import pytest

from tests.helpers.cli import assert_one_line_error, softarm

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def test_recording_with_another_image_size_is_refused(tiny_checkpoint, tmp_path):
    (tmp_path / "narrow.toml").write_text("[camera]\nwidth = 40\norigin = [20.0, 3.0]\n")
    assert softarm("sim", "--config", "narrow.toml", "--duration", "0.2", "--out", "narrow.mcap", "-q",
                   cwd=tmp_path).returncode == 0
    result = softarm("replay", str(tiny_checkpoint.checkpoint), "narrow.mcap", "--png", "x.png", cwd=tmp_path)
    assert_one_line_error(result, "84x40 images", "trained on 84x52")
    assert not (tmp_path / "x.png").exists()


def test_replay_uses_a_truncated_recording_and_says_so(recordings, tiny_checkpoint, tmp_path):
    data = (recordings / "s0.mcap").read_bytes()
    (tmp_path / "cut.mcap").write_bytes(data[:int(len(data) * 0.7)])
    result = softarm("replay", str(tiny_checkpoint.checkpoint), "cut.mcap", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "truncated: recovered" in result.stderr and "imagined frames" in result.stdout


def test_replay_reads_through_the_sensor_noise_asked_for(recordings, tiny_checkpoint, tmp_path):
    clean = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s1.mcap"), cwd=tmp_path)
    noisy = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s1.mcap"),
                    "--sensor-noise", "noise=1e-2,seed=4", cwd=tmp_path)
    assert clean.returncode == 0 and noisy.returncode == 0, noisy.stderr
    assert clean.stdout != noisy.stdout  # other signals, other imagination
    for bad, words in (("loudness=3", ["loudness", "KEY=VALUE"]), ("noise=lots", ["'lots'", "not a number"]),
                       ("noise=-1", ["sensing.noise", ">= 0"]), ("dropout_sensor=9", ["sensing.dropout_sensor"])):
        result = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s1.mcap"), "--png", "x.png",
                         "--sensor-noise", bad, cwd=tmp_path)
        assert_one_line_error(result, *words)
        assert not (tmp_path / "x.png").exists()
