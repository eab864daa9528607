"""`softarm import` recovers what the robot-style bag hid: the arm's mask, the clock offset, the dropped frames
and the stretch, judged against the softarm recording the bag was made from."""

import json

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

from softarm.model.metrics import iou_per_frame
from softarm.record.reader import read_recording


def native_index(rec, native, start: float) -> np.ndarray:
    """The source recording's frame at each imported frame's time (the bag's clock starts at `start`)."""
    t0 = rec.model["source"]["found"]["t0"] - start
    return np.round((t0 + rec.times) / native.frame_dt).astype(int)


def test_import_finds_the_lag_the_gaps_and_the_masks(recordings, robot_bag, imported):
    report, path = imported
    native = read_recording(recordings / "s0.mcap")
    rec = read_recording(path)
    assert abs(report.lag - robot_bag.offset) < 1 / 30                   # within one camera frame
    assert abs(report.camera_hz - 30) < 0.5 and abs(report.sensor_hz - 100) < 1
    assert report.dropped == len(robot_bag.dropped) and rec.model["gaps"] == report.gaps
    assert abs(report.frame_dt - 0.01) < 1e-12 and abs(rec.seen.sum() - robot_bag.frames) <= 1
    assert (rec.imported and rec.positions is None and not rec.seen[report.gaps].any() and rec.seen.sum() > 100
            and rec.frame_dt == 0.01)
    k = native_index(rec, native, 1_700_000_000.0)
    assert iou_per_frame(rec.frames[rec.seen].astype(float), native.frames[k[rec.seen]]).mean() > 0.93
    at = rec.times + rec.model["source"]["found"]["t0"] - 1_700_000_000.0 + report.lag - robot_bag.offset
    for imported_signal, source in ((rec.stretch, native.stretch),
                                    (rec.displacement[:, None], native.displacement[:, None])):
        expected = np.stack([np.interp(at, native.times, s) for s in source.T], axis=1)
        assert np.abs(imported_signal - expected).max() < 0.04 * np.abs(source).max()


def test_an_imported_recording_opens_in_a_plain_mcap_reader(imported):
    report, path = imported
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        meta = {m.name: m.metadata for m in reader.iter_metadata()}
        images = [img for _, _, _, img in reader.iter_decoded_messages(topics=["/camera/image"])]
        stretch = [json.loads(m.data) for _, _, m in reader.iter_messages(topics=["/arm/stretch"])]
    model = json.loads(meta["softarm"]["model"])
    assert model["kind"] == "imported" and model["source"]["settings"]["mask"] == "auto"
    assert len(images) == report.frames - len(report.gaps) and len(stretch) == report.frames
    assert images[0].encoding == "mono8" and (images[0].width, images[0].height) == (52, 84)
    assert meta["softarm.run"] == {"complete": "true", "frames": str(report.frames)}
    assert model["source"]["found"]["lag"] == report.lag and "sha256" in model["source"]


def test_the_preview_shows_frames_beside_their_masks(robot_bag, tmp_path):
    from PIL import Image

    from softarm.real.preview import preview_log
    from softarm.real.settings import ImportSettings

    settings = ImportSettings(robot_bag.camera_topic, f"{robot_bag.stretch_topic}:data", roi=robot_bag.roi)
    png = preview_log(robot_bag.path, tmp_path / "p.png", settings, count=3)
    image = Image.open(png)
    assert image.height > 200 and image.width > 3 * 3 * 100 and not (tmp_path / "p.png.part").exists()


def test_an_imported_recording_opens_in_rerun(imported, tmp_path):
    import subprocess

    from tests.helpers.cli import RERUN

    _, path = imported
    assert subprocess.run([RERUN, "mcap", "convert", str(path), "-o", str(tmp_path / "i.rrd")],
                          capture_output=True).returncode == 0
    assert subprocess.run([RERUN, "rrd", "verify", str(tmp_path / "i.rrd")], capture_output=True).returncode == 0


def test_a_background_frame_is_subtracted(recordings, robot_bag, tmp_path):
    """With a photo of the empty scene, the arm is what differs from it: no colour rule needed."""
    from softarm.real.convert import import_log
    from softarm.real.robot_camera import ArmCamera
    from softarm.real.robot_log import RobotLogSettings
    from softarm.real.settings import ImportSettings

    native = read_recording(recordings / "s0.mcap")
    ArmCamera(native, RobotLogSettings(), np.random.default_rng(0)).background.save(tmp_path / "empty.png")
    settings = ImportSettings(robot_bag.camera_topic, f"{robot_bag.stretch_topic}:data", roi=robot_bag.roi,
                              background=str(tmp_path / "empty.png"), mask="diff>otsu", lag=robot_bag.offset)
    import_log(robot_bag.path, tmp_path / "d.mcap", settings)
    rec = read_recording(tmp_path / "d.mcap")
    k = native_index(rec, native, 1_700_000_000.0)
    assert iou_per_frame(rec.frames[rec.seen].astype(float), native.frames[k[rec.seen]]).mean() > 0.9


@pytest.mark.slow
def test_a_scale_given_or_read_from_the_arms_length_puts_tip_errors_in_mm(recordings, robot_bag, imported, tmp_path):
    """--scale (the camera's own, as robot-log prints it) gives the native frames' scale exactly; --arm-length (the
    arm's length as it hangs) reads it from the masks to within the pixel their extent is rounded to."""
    from softarm.config import load_config
    from softarm.real.convert import import_log
    from softarm.real.settings import ImportSettings
    from softarm.sim.batch import arm_batch

    native = read_recording(recordings / "s0.mcap", nodes=False)
    hanging = arm_batch(load_config(), seeds=[0]).positions[0][:, 1]
    base = dict(camera=robot_bag.camera_topic, sensors=f"{robot_bag.stretch_topic}:data", roi=robot_bag.roi)
    for name, extra, tolerance in (("scale", {"scale": robot_bag.pixels_per_metre}, 1e-9),
                                   ("length", {"arm_length": float(hanging.max() - hanging.min())}, 0.02)):
        report = import_log(robot_bag.path, tmp_path / f"{name}.mcap", ImportSettings(**base, **extra))
        rec = read_recording(tmp_path / f"{name}.mcap")
        assert rec.pixels_per_metre == report.pixels_per_metre
        assert abs(rec.pixels_per_metre / native.pixels_per_metre - 1) <= tolerance, (name, rec.pixels_per_metre)
    assert np.isnan(read_recording(imported[1]).pixels_per_metre)  # without either: unknown
