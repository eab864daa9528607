"""Bad inputs to `softarm import` each get one line that says what to fix, and leave no output behind."""

import pytest
from mcap_ros2.writer import Writer

from tests.helpers.cli import assert_one_line_error, softarm

IMAGE_DEFINITION = ("std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
                    "uint32 step\nuint8[] data\n" + "=" * 80 + "\nMSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\n"
                    "string frame_id\n" + "=" * 80 + "\nMSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n")


@pytest.fixture(scope="module")
def yuv_bag(tmp_path_factory):
    """A log whose camera is yuv422, which softarm does not decode."""
    path = tmp_path_factory.mktemp("yuv") / "yuv.mcap"
    with open(path, "wb") as f:
        writer = Writer(f)
        schema = writer.register_msgdef("sensor_msgs/msg/Image", IMAGE_DEFINITION)
        for k in range(3):
            writer.write_message("/cam", schema, {"header": {"stamp": {"sec": k, "nanosec": 0}, "frame_id": "c"},
                                                  "height": 2, "width": 2, "encoding": "yuv422", "is_bigendian": 0,
                                                  "step": 4, "data": bytes(8)}, log_time=k * 10**9,
                                 publish_time=k * 10**9)
        writer.finish()
    return path


def run_import(bag, tmp_path, *extra: str, camera: str = "/camera/image_raw/compressed",
               sensors: str = "/arm/stretch:data"):
    result = softarm("import", str(bag), "--camera", camera, "--sensors", sensors, "--out", "out.mcap", *extra,
                     cwd=tmp_path)
    assert not (tmp_path / "out.mcap").exists() and not list(tmp_path.glob("*.part"))
    return result


def test_a_topic_not_in_the_log_is_named_with_the_topics_that_are(robot_bag, tmp_path):
    message = assert_one_line_error(run_import(robot_bag.path, tmp_path, camera="/nope"), "/nope")
    assert ("/camera/image_raw/compressed" in message and "/arm/stretch:data" in message
            and "/arm/command:position" in message)


@pytest.mark.slow
def test_a_field_path_that_does_not_exist_is_named(robot_bag, tmp_path):
    assert_one_line_error(run_import(robot_bag.path, tmp_path, sensors="/arm/stretch:nope"), "nope", "data")


def test_an_unsupported_encoding_is_named(yuv_bag, tmp_path):
    assert_one_line_error(run_import(yuv_bag, tmp_path, camera="/cam", sensors="/cam:height"), "yuv422")


@pytest.mark.slow
def test_camera_and_sensors_without_overlap_are_refused(robot_bag, tmp_path):
    assert_one_line_error(run_import(robot_bag.path, tmp_path, "--lag", "30"), "share no time")


@pytest.mark.slow
def test_a_mask_empty_everywhere_suggests_a_threshold(robot_bag, tmp_path):
    assert_one_line_error(run_import(robot_bag.path, tmp_path, "--mask", "r>255"), "empty",
                          "threshold")


@pytest.mark.slow
def test_a_drive_of_several_values_is_refused(robot_bag, tmp_path):
    assert_one_line_error(run_import(robot_bag.path, tmp_path, "--drive", "/arm/stretch:data"), "one command")


def test_a_lag_that_is_not_a_number_is_refused(robot_bag, tmp_path):
    assert_one_line_error(run_import(robot_bag.path, tmp_path, "--lag", "nan"), "--lag")


@pytest.mark.slow
def test_a_mask_that_never_changes_gives_no_lag(robot_bag, tmp_path):
    assert_one_line_error(run_import(robot_bag.path, tmp_path, "--mask", "gray<256"),
                          "lag", "--lag")


def test_a_robot_log_needs_a_simulated_recording(imported, tmp_path):
    _, path = imported
    result = softarm("robot-log", str(path), "--out", "bag.mcap", cwd=tmp_path)
    assert_one_line_error(result, "node positions")
    assert not list(tmp_path.iterdir())
