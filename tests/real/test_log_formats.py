"""The same robot log as MCAP, as a ROS 2 bag (sqlite3) and as a ROS 1 bag imports to the same recording; a file that
is none of them is refused in one line that says what it looks like."""

import numpy as np
import pytest

from softarm.errors import RecordingError
from softarm.real.formats import open_log
from softarm.record.reader import read_recording
from tests.helpers.bags import ros1_bag, ros2_bag


@pytest.mark.slow
def test_mcap_ros2_and_ros1_bags_of_one_log_import_to_the_same_recording(robot_bag, imported, tmp_path):
    from softarm.real.convert import import_log
    from softarm.real.settings import ImportSettings

    settings = ImportSettings(robot_bag.camera_topic, f"{robot_bag.stretch_topic}:data",
                              f"{robot_bag.drive_topic}:position", roi=robot_bag.roi)
    reference = read_recording(imported[1])
    for name, bag in (("ros2", ros2_bag(robot_bag.path, tmp_path / "ros2")),
                      ("ros1", ros1_bag(robot_bag.path, tmp_path / "log.bag"))):
        report = import_log(bag, tmp_path / f"{name}.mcap", settings)
        rec = read_recording(tmp_path / f"{name}.mcap")
        assert report.lag == imported[0].lag and report.gaps == imported[0].gaps, name
        assert np.array_equal(rec.times, reference.times) and np.array_equal(rec.seen, reference.seen), name
        assert np.array_equal(rec.frames, reference.frames), name
        assert np.array_equal(rec.stretch, reference.stretch) and np.array_equal(rec.displacement,
                                                                                 reference.displacement), name


@pytest.mark.slow
def test_a_bag_lists_its_topics_types_and_fields_as_the_mcap_log_does(robot_bag, tmp_path):
    with open_log(robot_bag.path) as log:
        expected = {name: (t.schema, t.messages) for name, t in log.topics.items()}
        described = log.describe()
    for bag, encoding in ((ros2_bag(robot_bag.path, tmp_path / "ros2"), "cdr"),
                          (ros1_bag(robot_bag.path, tmp_path / "log.bag"), "ros1")):
        with open_log(bag) as log:
            assert {name: (t.schema, t.messages) for name, t in log.topics.items()} == expected
            assert {t.encoding for t in log.topics.values()} == {encoding} and log.describe() == described
            assert abs(log.seconds() - 4.0) < 0.05
            stretch = log.first(robot_bag.stretch_topic)
            assert stretch.header.stamp.sec > 1_600_000_000 and len(stretch.data) == 4


@pytest.mark.parametrize("content, words", [
    (b"\x89PNG\r\n\x1a\n" + bytes(40), "a PNG image"), (b'{"t": 0.0, "stretch": [0.1]}\n', "a text file (JSON?)"),
    (b"", "empty"), (bytes(range(256)), "a binary file of no format"), (b"#ROSBAG V1.2\n", "older version")])
def test_a_file_of_another_format_is_refused_naming_what_it_looks_like(tmp_path, content, words):
    path = tmp_path / "log.mcap"
    path.write_bytes(content)
    with pytest.raises(RecordingError, match="MCAP file, a ROS 1 .bag or a ROS 2 bag folder") as refused:
        open_log(path)
    assert words in str(refused.value) and "\n" not in str(refused.value)


def test_a_folder_or_a_database_without_the_bags_metadata_is_refused(tmp_path):
    with pytest.raises(RecordingError, match="without metadata.yaml, not a ROS 2 bag"):
        open_log(tmp_path)
    database = tmp_path / "bag_0.db3"
    database.write_bytes(b"SQLite format 3\x00" + bytes(100))
    with pytest.raises(RecordingError, match="give the bag's folder"):
        open_log(database)
    with pytest.raises(RecordingError, match="not found"):
        open_log(tmp_path / "missing.bag")


def test_no_output_replaces_a_file_of_a_bag_folder(tmp_path):
    from softarm.errors import OutputError
    from softarm.real.convert import import_log
    from softarm.real.settings import ImportSettings

    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    (bag / "bag_0.db3").write_bytes(b"SQLite format 3\x00")
    before = {p.name: p.read_bytes() for p in bag.iterdir()}
    for target in ("bag_0.db3", "metadata.yaml"):
        with pytest.raises(OutputError, match="is the input"):
            import_log(bag, bag / target, ImportSettings("/camera", "/stretch:data"), force=True)
    assert {p.name: p.read_bytes() for p in bag.iterdir()} == before


@pytest.mark.slow
def test_the_command_line_imports_a_bag_folder_and_refuses_a_picture_in_one_line(robot_bag, tmp_path):
    from tests.helpers.cli import assert_one_line_error, softarm

    bag = ros2_bag(robot_bag.path, tmp_path / "bag")
    topics = ("--camera", robot_bag.camera_topic, "--sensors", f"{robot_bag.stretch_topic}:data",
              "--roi", ",".join(map(str, robot_bag.roi)))
    done = softarm("import", str(bag), *topics, "--out", "rec.mcap", cwd=tmp_path)
    assert done.returncode == 0 and read_recording(tmp_path / "rec.mcap").imported, done.stderr
    (tmp_path / "photo.mcap").write_bytes(b"\xff\xd8\xff\xe0" + bytes(60))
    assert_one_line_error(softarm("import", "photo.mcap", *topics, "--out", "x.mcap", cwd=tmp_path),
                          "photo.mcap is a JPEG image, not a log softarm reads")
    assert not (tmp_path / "x.mcap").exists()
