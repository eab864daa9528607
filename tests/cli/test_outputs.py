"""Output paths of train and replay: refused before any work, in one line, leaving existing files alone."""

import pytest

from tests.helpers.cli import assert_one_line_error, softarm


@pytest.mark.slow
@pytest.mark.parametrize("command", ["train", "replay"])
def test_output_whose_parent_is_a_file_is_refused(recordings, tiny_checkpoint, tmp_path, command):
    (tmp_path / "afile").write_text("")
    args = {"train": ["train", str(recordings / "s0.mcap"), "--out", "afile/x.pt"],
            "replay": ["replay", str(tiny_checkpoint.checkpoint), str(recordings / "s0.mcap"), "--mcap",
                       "afile/x.mcap"]}
    assert_one_line_error(softarm(*args[command], cwd=tmp_path), "afile", "not a folder")


@pytest.mark.slow
@pytest.mark.parametrize("command", ["train", "replay"])
def test_existing_output_is_refused_without_force(recordings, tiny_checkpoint, tmp_path, command):
    (tmp_path / "old").write_text("precious")
    args = {"train": ["train", str(recordings / "s0.mcap"), "--out", "old"],
            "replay": ["replay", str(tiny_checkpoint.checkpoint), str(recordings / "s0.mcap"), "--rrd", "old"]}
    assert_one_line_error(softarm(*args[command], cwd=tmp_path), "old", "exists", "--force")
    assert (tmp_path / "old").read_text() == "precious"
