"""Replay on recordings it did not expect: another image size is refused, a truncated one is used
with a warning."""

from cli_helpers import assert_one_line_error, softarm


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
