"""The robot-style ROS 2 log holds the recording as a lab would log it: read back with the plain mcap and
mcap-ros2-support readers, its camera shows the recording's frames, its stretch is the recording's on a clock
that runs `sensor_offset` ahead, and its messages lie in receive-time order."""

import io

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.records import Message
from mcap.stream_reader import StreamReader
from mcap_ros2.decoder import DecoderFactory
from PIL import Image

from softarm.errors import ConfigError
from softarm.real import robot_camera
from softarm.real.robot_log import RobotLogSettings, make_robot_log
from softarm.record.reader import read_recording

ARM = np.array([215, 95, 35])


def decoded(path, topic: str) -> list:
    """(log_time ns, message) of every message on a topic, decoded by mcap-ros2-support alone."""
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        return [(m.log_time, msg) for _, _, m, msg in reader.iter_decoded_messages(topics=[topic])]


def stamp_ns(header) -> int:
    return header.stamp.sec * 1_000_000_000 + header.stamp.nanosec


def small_frame(rgb: np.ndarray, roi: tuple[int, int, int, int], shape: tuple[int, int]) -> np.ndarray:
    """The arm's mask at the model camera's size: colour distance to the arm, averaged over each block of the ROI."""
    x, y, w, h = roi
    near = np.linalg.norm(rgb[y:y + h, x:x + w].astype(float) - ARM, axis=-1) < 75
    return near.reshape(shape[0], h // shape[0], shape[1], w // shape[1]).mean((1, 3)) > 0.5


@pytest.fixture(scope="module")
def jpeg_log(recordings, tmp_path_factory):
    rec = read_recording(recordings / "s0.mcap")
    return rec, make_robot_log(recordings / "s0.mcap", tmp_path_factory.mktemp("robot") / "bag.mcap")


@pytest.mark.slow
def test_the_camera_shows_the_recording_frames_minus_the_dropped_ones(jpeg_log):
    rec, log = jpeg_log
    settings = RobotLogSettings()
    expected = int(np.sum(np.rint(np.arange(1000) / settings.camera_hz / rec.frame_dt) < len(rec.times)))
    assert len(log.dropped) == settings.dropped and log.frames == expected - settings.dropped
    assert min(log.dropped) >= 10 and max(log.dropped) < expected - 10
    (x, y, w, h), (height, width) = log.roi, rec.frames.shape[1:]
    s = min(640 // width, 480 // height)
    assert (w, h) == (s * width, s * height) and (x, y) == ((640 - w) // 2, (480 - h) // 2)
    images = decoded(log.path, log.camera_topic)
    assert log.camera_topic == "/camera/image_raw/compressed" and len(images) == log.frames
    start_ns = round(settings.start * 1e9)
    k = np.rint(log.camera_times / rec.frame_dt).astype(int)
    assert [stamp_ns(m.header) for _, m in images] == list(start_ns + np.rint(rec.times[k] * 1e9).astype(int))
    ious = []
    for (_, message), frame in zip(images, rec.frames[k].astype(bool)):
        rgb = np.asarray(Image.open(io.BytesIO(message.data)).convert("RGB"))
        assert rgb.shape == (480, 640, 3) and "jpeg" in message.format
        seen = small_frame(rgb, log.roi, frame.shape)
        ious.append((seen & frame).sum() / (seen | frame).sum())
    assert np.mean(ious) > 0.95


def test_stretch_and_drive_are_the_recording_on_the_controller_clock(jpeg_log):
    rec, log = jpeg_log
    settings = RobotLogSettings()
    true_ns = round(settings.start * 1e9) + np.rint(rec.times * 1e9).astype(np.int64)
    stretch = decoded(log.path, log.stretch_topic)
    assert len(stretch) == len(rec.times)
    np.testing.assert_allclose([m.data for _, m in stretch], rec.stretch.astype(np.float32), rtol=1e-6, atol=0)
    lead = (np.array([stamp_ns(m.header) for _, m in stretch]) - true_ns) / 1e9
    assert np.all(np.abs(lead - log.offset) <= 4 * settings.sensor_jitter) and log.offset == settings.sensor_offset
    assert np.all(np.diff([stamp_ns(m.header) for _, m in stretch]) > 0)
    assert np.all(np.array([t for t, _ in stretch]) >= true_ns)  # received after it happened
    drive = decoded(log.path, log.drive_topic)
    assert len(drive) == len(rec.times) and all(m.name == ["top"] for _, m in drive)
    np.testing.assert_array_equal([m.position[0] for _, m in drive], rec.displacement)
    assert [stamp_ns(m.header) for _, m in drive] == list(true_ns + round(settings.sensor_offset * 1e9))


def test_messages_lie_in_receive_time_order_with_embedded_ros2_schemas(jpeg_log):
    _, log = jpeg_log
    with open(log.path, "rb") as f:
        log_times = [r.log_time for r in StreamReader(f).records if isinstance(r, Message)]
    assert len(log_times) > 0 and np.all(np.diff(log_times) >= 0)
    with open(log.path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert reader.get_header().profile == "ros2"
    assert {s.name for s in summary.schemas.values()} == {
        "sensor_msgs/msg/CompressedImage", "softarm_msgs/msg/Stretch", "sensor_msgs/msg/JointState"}
    assert all(s.encoding == "ros2msg" for s in summary.schemas.values())
    assert all(c.message_encoding == "cdr" for c in summary.channels.values())
    assert not log.path.with_name(log.path.name + ".part").exists()


def test_float32_multiarray_stretch_and_raw_images_decode(recordings, tmp_path):
    rec = read_recording(recordings / "three_sensors.mcap")
    settings = RobotLogSettings(width=320, height=240, image_format="rgb8", sensor_header=False, dropped=2, seed=3)
    log = make_robot_log(recordings / "three_sensors.mcap", tmp_path / "raw.mcap", settings)
    stretch = decoded(log.path, "/arm/stretch")
    assert len(stretch) == len(rec.times) and not hasattr(stretch[0][1], "header")
    assert all(m.layout.dim == [] and m.layout.data_offset == 0 for _, m in stretch)
    np.testing.assert_allclose([m.data for _, m in stretch], rec.stretch.astype(np.float32), rtol=1e-6, atol=0)
    images = decoded(log.path, "/camera/image_raw")
    assert log.camera_topic == "/camera/image_raw" and len(images) == log.frames == len(log.camera_times)
    first = images[0][1]
    assert (first.width, first.height, first.encoding, first.step) == (320, 240, "rgb8", 960)
    rgb = np.frombuffer(first.data, np.uint8).reshape(240, 320, 3)
    frame = rec.frames[int(round(log.camera_times[0] / rec.frame_dt))].astype(bool)
    seen = small_frame(rgb, log.roi, frame.shape)
    assert (seen & frame).sum() / (seen | frame).sum() > 0.9
    again = make_robot_log(recordings / "three_sensors.mcap", tmp_path / "again.mcap", settings)
    assert again.path.read_bytes() == log.path.read_bytes()  # all follows from the seed


def test_a_failed_write_leaves_no_file(recordings, tmp_path, monkeypatch):
    def broken(*_):
        raise RuntimeError("camera unplugged")

    monkeypatch.setattr(robot_camera.ArmCamera, "image", broken)
    with pytest.raises(RuntimeError, match="camera unplugged"):
        make_robot_log(recordings / "three_sensors.mcap", tmp_path / "bag.mcap")
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ConfigError, match="image-format"):
        make_robot_log(recordings / "three_sensors.mcap", tmp_path / "bag.mcap", RobotLogSettings(image_format="bmp"))


def camera_images(log) -> np.ndarray:
    """(frames, H, W, 3) uint8 of the log's camera, decoded by mcap-ros2-support and PIL."""
    return np.stack([np.asarray(Image.open(io.BytesIO(m.data)).convert("RGB"))
                     for _, m in decoded(log.path, log.camera_topic)])


@pytest.mark.slow
def test_scene_options_change_what_the_camera_sees_and_nothing_else(recordings, tmp_path):
    """A dark arm on a light flat wall, light that drifts, a smeared arm and a swinging object: each where and as
    large as asked, the arm still exactly where the recording puts it."""
    rec = read_recording(recordings / "s0.mcap")
    base = dict(width=320, height=240, image_format="png", light_noise=0.0, pixel_noise=0.0, blur=0.0, dropped=0)
    plain = make_robot_log(recordings / "s0.mcap", tmp_path / "plain.mcap", RobotLogSettings(**base))
    k = np.rint(plain.camera_times / rec.frame_dt).astype(int)
    (x, y, w, h), shape = plain.roi, rec.frames.shape[1:]
    arm = np.zeros((len(k), 240, 320), bool)
    arm[:, y:y + h, x:x + w] = np.repeat(np.repeat(rec.frames[k].astype(bool), h // shape[0], 1), w // shape[1], 2)
    shifts = [(dy, dx) for dy in range(-3, 4) for dx in range(-3, 4)]
    inner = np.logical_and.reduce([np.roll(arm, shift, (1, 2)) for shift in shifts])   # 3 px inside the arm
    outer = ~np.logical_or.reduce([np.roll(arm, shift, (1, 2)) for shift in shifts])   # 3 px clear of it
    outer[:, :y + 3], outer[:, y + h - 3:], outer[:, :, :x + 3], outer[:, :, x + w - 3:] = False, False, False, False

    dark = dict(base, arm_rgb=(40, 35, 45), scene_rgb=(200, 200, 190), texture=0.0)
    seen = camera_images(make_robot_log(recordings / "s0.mcap", tmp_path / "dark.mcap", RobotLogSettings(**dark)))
    lit = seen[inner].mean(0) / np.array([40, 35, 45])
    assert np.all(np.abs(lit - 1) < 0.1)                           # the arm in its colour (its shading within 10 %)
    assert np.abs(seen[outer].astype(float) - [200, 200, 190]).max() <= 2  # a flat wall: no texture at all

    drift = camera_images(make_robot_log(recordings / "s0.mcap", tmp_path / "drift.mcap",
                                         RobotLogSettings(**dict(base, lighting_drift=0.3))))
    plain_images = camera_images(plain)
    ratio = drift[:, outer[0]].mean((1, 2)) / plain_images[:, outer[0]].mean((1, 2))
    assert abs(ratio[0] - 0.7) < 0.02 and abs(ratio[-1] - 1.3) < 0.03 and np.all(np.diff(ratio) > -0.01)

    smeared = camera_images(make_robot_log(recordings / "s0.mcap", tmp_path / "blur.mcap",
                                           RobotLogSettings(**dict(base, motion_blur=0.05))))
    smear = np.abs(smeared.astype(int) - plain_images).sum(-1) > 30  # where the exposure moved the arm's cover
    near = np.logical_or.reduce([np.roll(arm, (dy, dx), (1, 2))
                                 for dy in range(-12, 13, 3) for dx in range(-12, 13, 3)])
    assert smear.sum() > 0.05 * arm.sum() and not smear[~near].any()

    swinging = camera_images(make_robot_log(recordings / "s0.mcap", tmp_path / "swing.mcap",
                                            RobotLogSettings(**dict(base, distractor=True))))
    changed = np.abs(swinging.astype(int) - plain_images).sum(-1) > 30
    assert not changed[inner].any()                                # behind the arm, never over it
    where = [np.argwhere(c).mean(0) for c in changed]
    sizes = changed.sum((1, 2))
    assert (np.median(sizes) > 500 and sizes.min() > 50
            and np.linalg.norm(where[0] - where[-1]) > 20), (sizes.min(), where[0], where[-1])


@pytest.mark.parametrize("field, value, words", [("arm_rgb", (300, 0, 0), "--arm-colour"),
                                                 ("scene_rgb", (1, 2), "--scene-colour"),
                                                 ("lighting_drift", 1.5, "--lighting-drift"),
                                                 ("motion_blur", float("nan"), "--motion-blur"),
                                                 ("texture", -1.0, "--texture"), ("seed", -1, "--seed")])
def test_scene_options_out_of_range_are_refused_before_anything_is_written(recordings, tmp_path, field, value, words):
    with pytest.raises(ConfigError, match=words):
        make_robot_log(recordings / "three_sensors.mcap", tmp_path / "bag.mcap", RobotLogSettings(**{field: value}))
    assert list(tmp_path.iterdir()) == []
