"""`check_outputs` refuses two names of one file (a resolved path, a symlink, a hard link) among the outputs and
between an output and an input, for a batch of any size; checked with the operating system's own answer
(`os.path.samefile`) on the files it makes."""

import os

import pytest

from softarm.errors import OutputError
from softarm.files import check_outputs


def test_a_large_batch_of_distinct_outputs_passes(tmp_path):
    check_outputs([tmp_path / "out" / f"x_arm{i}.mcap" for i in range(512)], force=False, inputs=[tmp_path / "in.toml"])


@pytest.mark.parametrize("name", ["x_arm7.mcap", "./x_arm7.mcap", "sub/../x_arm7.mcap", "link.mcap", "hard.mcap"])
def test_two_names_of_one_output_are_refused(tmp_path, name):
    (tmp_path / "sub").mkdir()
    (tmp_path / "x_arm7.mcap").write_bytes(b"old")
    (tmp_path / "link.mcap").symlink_to(tmp_path / "x_arm7.mcap")
    os.link(tmp_path / "x_arm7.mcap", tmp_path / "hard.mcap")
    assert os.path.samefile(tmp_path / name, tmp_path / "x_arm7.mcap")
    outputs = [tmp_path / f"x_arm{i}.mcap" for i in range(20)]
    with pytest.raises(OutputError, match="are one file"):
        check_outputs([*outputs, tmp_path / name], force=True)
    with pytest.raises(OutputError, match="is the input"):
        check_outputs(outputs, force=True, inputs=[tmp_path / name])
