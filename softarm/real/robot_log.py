"""A softarm recording rewritten as the ROS 2 MCAP bag a lab with a real soft arm would log.

An importer of such logs must find the arm in a big, noisy colour image, read the stretch and undo the lag between
two clocks. Real bags come without ground truth; this one is made from a recording, where mask, stretch and lag are
known: a 30 Hz camera (JPEG, PNG or rgb8; flicker, blur, noise, dropped frames, transport delays) and a 100 Hz
sensor/drive controller whose clock runs `sensor_offset` ahead, with jittered stamps. All follows from the seed.
"""

import heapq
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterator

import numpy as np
from mcap.writer import CompressionType
from mcap_ros2.writer import Writer

from softarm import limits
from softarm.errors import ConfigError
from softarm.files import atomic_path, check_outputs, claimed, made_folders
from softarm.interrupt import Escalated, Interrupted, Stopped, stop_on_signal
from softarm.real.robot_settings import RobotLogSettings, ros_header
from softarm.record.reader import Recording, read_recording
from softarm.record.recording import needs_nodes_error

if TYPE_CHECKING:
    from softarm.real.robot_camera import ArmCamera

_SEP = "\n" + "=" * 80 + "\nMSG: "
_TIME = "int32 sec\nuint32 nanosec\n"
_HEADER = "builtin_interfaces/Time stamp\nstring frame_id\n"
_STAMPED = (("std_msgs/Header", _HEADER), ("builtin_interfaces/Time", _TIME))
_DEFINITIONS: dict[str, tuple[str, tuple[tuple[str, str], ...]]] = {
    "sensor_msgs/msg/CompressedImage": ("std_msgs/Header header\nstring format\nuint8[] data\n", _STAMPED),
    "sensor_msgs/msg/Image": ("std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n"
                              "uint8 is_bigendian\nuint32 step\nuint8[] data\n", _STAMPED),
    "sensor_msgs/msg/JointState": ("std_msgs/Header header\nstring[] name\nfloat64[] position\n"
                                   "float64[] velocity\nfloat64[] effort\n", _STAMPED),
    "softarm_msgs/msg/Stretch": ("# Stretch of each sensor, m\nstd_msgs/Header header\nfloat32[] data\n", _STAMPED),
    "std_msgs/msg/Float32MultiArray": ("MultiArrayLayout  layout\nfloat32[]         data\n", (
        ("std_msgs/MultiArrayLayout", "MultiArrayDimension[] dim\nuint32 data_offset\n"),
        ("std_msgs/MultiArrayDimension", "string label\nuint32 size\nuint32 stride\n"))),
}


@dataclass(frozen=True)
class RobotLog:
    """What was written, and the ground truth an importer should recover (roi, offset, dropped frames)."""
    path: Path
    camera_topic: str
    stretch_topic: str
    drive_topic: str
    roi: tuple[int, int, int, int]  # x, y, w, h: where the recording's camera view lies in the big image
    offset: float                   # s: the sensor clock's lead over the camera's
    dropped: tuple[int, ...]        # indices of dropped camera frames, in the camera's own sequence
    frames: int                     # camera frames written
    camera_times: np.ndarray        # (frames,) recording time (s) of each written camera frame
    pixels_per_metre: float         # the camera's own pixels per metre in the arm's plane


def _ns(seconds: Any) -> Any:
    return np.rint(np.asarray(seconds, np.float64) * 1e9).astype(np.int64)


def _camera_plan(frames: int, frame_dt: float, settings: RobotLogSettings,
                 rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Recording frame shown by each camera frame j (nearest j / camera_hz), and the sorted dropped j."""
    j = np.arange(int(np.ceil(frames * frame_dt * settings.camera_hz)) + 2)
    shown = np.rint(j / settings.camera_hz / frame_dt).astype(np.int64)
    shown = shown[shown < frames]
    candidates = np.arange(10, len(shown) - 10)
    count = min(settings.dropped, len(candidates))
    return shown, np.sort(rng.choice(candidates, count, replace=False)) if count > 0 else np.zeros(0, np.int64)


def _sensor_stamps(true_ns: np.ndarray, settings: RobotLogSettings, rng: np.random.Generator) -> np.ndarray:
    """Stretch stamps on the controller's clock: offset plus clipped jitter, kept strictly increasing."""
    jitter = np.clip(rng.normal(0.0, 1.0, len(true_ns)), -3, 3) * settings.sensor_jitter
    stamps = np.sort(true_ns + _ns(settings.sensor_offset + jitter))
    steps = np.arange(len(stamps))
    return np.maximum.accumulate(stamps - steps) + steps


def _streams(rec: Recording, settings: RobotLogSettings, rng: np.random.Generator,
             camera: "ArmCamera") -> tuple[Iterator[tuple], Iterator[tuple], Iterator[tuple], tuple, np.ndarray]:
    """The three topics' (log_time, topic, message) streams, each in log-time order, rendered lazily."""
    true_ns = _ns(settings.start) + _ns(rec.times)
    shown, dropped = _camera_plan(len(rec.times), rec.frame_dt, settings, rng)
    kept = np.setdiff1d(np.arange(len(shown)), dropped)
    stretch_ns = _sensor_stamps(true_ns, settings, rng)
    stretch_log = true_ns + _ns(np.clip(rng.normal(2e-3, 1e-3, len(true_ns)), 0, 5e-3))  # transport delays
    camera_log = true_ns[shown] + _ns(np.clip(rng.normal(20e-3, 3e-3, len(shown)), 11e-3, 29e-3))
    drive_ns = true_ns + _ns(settings.sensor_offset)
    stretch = rec.stretch.astype(np.float32)
    topic = _camera_topic(settings)[0]
    smear = int(round(settings.motion_blur / rec.frame_dt))  # recording frames within one exposure, before the last
    span = max(float(rec.times[-1]), 1e-9)

    def exposure(k: int) -> np.ndarray:
        return rec.positions[k] if smear == 0 else rec.positions[max(0, k - smear):k + 1]

    images = ((int(camera_log[j]), topic, camera.message(exposure(shown[j]), int(true_ns[shown[j]]),
                                                         float(rec.times[shown[j]]) / span))
              for j in kept)
    stretches = ((int(stretch_log[k]), "/arm/stretch",
                  {"header": ros_header(int(stretch_ns[k]), "arm"), "data": stretch[k].tolist()}
                  if settings.sensor_header
                  else {"layout": {"dim": [], "data_offset": 0}, "data": stretch[k].tolist()})
                 for k in range(len(true_ns)))
    drives = ((int(true_ns[k]) + 1_000_000, "/arm/command",
               {"header": ros_header(int(drive_ns[k]), "arm"), "name": ["top"],
                "position": [float(rec.displacement[k])], "velocity": [], "effort": []})
              for k in range(len(true_ns)))
    return images, stretches, drives, tuple(int(j) for j in dropped), rec.times[shown[kept]]


def _camera_topic(settings: RobotLogSettings) -> tuple[str, str]:
    """image_transport's topic and type: the compressed one, or the raw one for rgb8."""
    if settings.image_format == "rgb8":
        return "/camera/image_raw", "sensor_msgs/msg/Image"
    return "/camera/image_raw/compressed", "sensor_msgs/msg/CompressedImage"


def make_robot_log(recording: str | Path, out: str | Path, settings: RobotLogSettings | None = None,
                   force: bool = False) -> RobotLog:
    """Write `out`, a ROS 2 MCAP bag of `recording` as a lab's robot would log it, for testing log importers; an
    existing `out` is replaced only with `force`, the recording never. Ctrl-C (or SIGTERM, SIGHUP) stops it before
    the next message, with nothing written (the bag is written whole or not at all)."""
    settings = settings or RobotLogSettings()
    if settings.image_format not in ("jpeg", "png", "rgb8"):
        raise ConfigError(f"--image-format {settings.image_format!r}: give jpeg, png or rgb8")
    limits.finite("--offset", settings.sensor_offset, 60.0)
    check_scene(settings)
    check_outputs([out], force=force, inputs=[recording])
    rec = read_recording(recording)
    if rec.positions is None or rec.displacement is None:
        raise needs_nodes_error(rec, "a robot-style log (its camera draws the arm from them)")
    rng = np.random.default_rng(settings.seed)
    from softarm.real.robot_camera import ArmCamera  # PIL: only when a log is made

    camera = ArmCamera(rec, settings, rng)
    images, stretches, drives, dropped, camera_times = _streams(rec, settings, rng, camera)
    types = {_camera_topic(settings)[0]: _camera_topic(settings)[1],
             "/arm/stretch": "softarm_msgs/msg/Stretch" if settings.sensor_header else "std_msgs/msg/Float32MultiArray",
             "/arm/command": "sensor_msgs/msg/JointState"}
    try:
        with stop_on_signal() as caught, made_folders([out]), claimed([out]), atomic_path(out) as part, \
                open(part, "wb") as f:
            writer = Writer(f, compression=CompressionType.ZSTD)
            schemas = {topic: writer.register_msgdef(name, _definition(name)) for topic, name in types.items()}
            sequence = dict.fromkeys(types, 0)
            for log_ns, topic, message in heapq.merge(images, stretches, drives, key=lambda m: m[0]):
                if caught:
                    raise Stopped()
                sequence[topic] += 1
                writer.write_message(topic, schemas[topic], message, log_ns, log_ns, sequence[topic])
            writer.finish()
    except Stopped:
        raise Interrupted(f"nothing was written to {out}") from None
    except Escalated:
        raise Escalated(f"stopped at once by a second stop request; nothing was written to {out}") from None
    return RobotLog(Path(out), _camera_topic(settings)[0], "/arm/stretch", "/arm/command", camera.roi,
                    settings.sensor_offset, dropped, len(camera_times), camera_times, camera.s * rec.pixels_per_metre)


def check_scene(settings: RobotLogSettings) -> None:
    """The scene options in range, each refused in one line naming its option."""
    for option, rgb in (("--arm-colour", settings.arm_rgb), ("--scene-colour", settings.scene_rgb)):
        if len(rgb) != 3 or not all(isinstance(v, (int, np.integer)) and 0 <= v <= 255 for v in rgb):
            raise ConfigError(f"{option} {','.join(map(str, rgb))}: give R,G,B, three integers 0..255")
    checks = (("--texture", settings.texture, 0.0, 3.0), ("--lighting-drift", settings.lighting_drift, 0.0, 0.9),
              ("--motion-blur", settings.motion_blur, 0.0, 0.2), ("--dropped", settings.dropped, 0, 10_000))
    for option, value, low, high in checks:
        if not (low <= value <= high):  # NaN fails too
            raise ConfigError(f"{option} {value}: give a value in {low:g}..{high:g}")
    if not 0 <= settings.seed < 2 ** 63:
        raise ConfigError(f"--seed {settings.seed}: give a whole number >= 0")


def _definition(name: str) -> str:
    """The full message definition, its dependencies after rosbag2's separators."""
    main, dependencies = _DEFINITIONS[name]
    return main + "".join(f"{_SEP}{dep}\n{text}" for dep, text in dependencies)
