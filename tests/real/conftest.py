import pytest

from softarm.real.robot_log import RobotLogSettings, make_robot_log


@pytest.fixture(scope="session")
def robot_bag(recordings, tmp_path_factory):
    """The 4 s seed-0 recording as a lab's ROS 2 bag (JPEG camera, stretch and drive on a clock 47 ms ahead)."""
    folder = tmp_path_factory.mktemp("bag")
    return make_robot_log(recordings / "s0.mcap", folder / "bag.mcap", RobotLogSettings())


@pytest.fixture(scope="session")
def imported(robot_bag, tmp_path_factory):
    """The bag imported with its ROI and drive: (report, recording path)."""
    from softarm.real.convert import import_log
    from softarm.real.settings import ImportSettings

    out = tmp_path_factory.mktemp("imported") / "imported.mcap"
    settings = ImportSettings(robot_bag.camera_topic, f"{robot_bag.stretch_topic}:data",
                              f"{robot_bag.drive_topic}:position", roi=robot_bag.roi)
    return import_log(robot_bag.path, out, settings), out
