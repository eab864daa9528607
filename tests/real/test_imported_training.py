"""An imported recording trains and replays like a simulated one: its camera gaps are neither trained on nor
scored, and what needs node positions says so in one line."""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.errors import ConfigError, RecordingError
from softarm.imagine.replay_data import compute_replay
from softarm.imagine.stream import StreamingImaginer
from softarm.learn.training import train
from softarm.real.convert import import_log
from softarm.real.robot_log import RobotLogSettings, make_robot_log
from softarm.real.settings import ImportSettings
from tests.helpers.tiny import TINY

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


SHORT = {**TINY, "train.train_fraction": 0.7, "train.test_fraction": 0.15}  # 4 s at 30 Hz: 18 frames to imagine


def test_an_imported_recording_trains_replays_and_skips_its_gaps(imported, tmp_path):
    report, path = imported
    result = train([path], load_config(overrides=SHORT), tmp_path / "m.pt")
    assert result.complete and np.isfinite(result.metrics["imagination"]["model"]["iou"])
    assert np.isnan(result.metrics["imagination"]["model"]["tip_mm"])  # no camera scale: no tip error in mm
    replay = compute_replay(result.checkpoint, path)
    assert (np.isnan(replay.iou[report.gaps]).all()
            and np.isfinite(replay.iou[replay.predicted & replay.recording.seen]).all())
    assert replay.nodes_px is None and 0 < replay.metrics["imagination"]["iou"] <= 1
    streamer = StreamingImaginer.from_checkpoint(result.checkpoint)  # online, sample by sample, as the replay
    streamed = [f for f in (streamer.step(stretch=sample) for sample in replay.recording.stretch[:60]) if f is not None]
    assert streamed and all(np.allclose(f.probabilities, replay.imagined[f.frame], atol=1e-5) for f in streamed)


def test_what_needs_node_positions_says_so(imported, tmp_path):
    _, path = imported
    with pytest.raises(RecordingError, match="imported from a robot's log, which has no node positions"):
        train([path], load_config(overrides={**SHORT, "sensing.pairs": [[3, 27]]}), tmp_path / "p.pt")
    with pytest.raises(ConfigError, match="node positions"):
        train([path], load_config(overrides={**SHORT, "train.node_target": 0.5}), tmp_path / "n.pt")


def test_sensors_without_a_header_fall_back_to_log_time_with_a_warning(recordings, tmp_path):
    bag = make_robot_log(recordings / "s0.mcap", tmp_path / "bag.mcap", RobotLogSettings(sensor_header=False))
    settings = ImportSettings(bag.camera_topic, f"{bag.stretch_topic}:data", roi=bag.roi, lag=0.0)
    with pytest.warns(UserWarning, match="no header stamp.*log time"):
        report = import_log(bag.path, tmp_path / "r.mcap", settings)
    assert report.frames > 100 and report.drive_hz is None
