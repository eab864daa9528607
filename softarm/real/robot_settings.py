"""What a robot-style log is made of: its settings, and the ROS header every message carries."""

from dataclasses import dataclass
from typing import Any

from softarm.errors import ConfigError


@dataclass(frozen=True)
class RobotLogSettings:
    """How the lab's camera and controller deviate from the ideal recording (all defaults: a typical lab rig)."""
    width: int = 640
    height: int = 480
    camera_hz: float = 30.0
    image_format: str = "jpeg"      # "jpeg" or "png" -> sensor_msgs/msg/CompressedImage;
                                    # "rgb8" -> sensor_msgs/msg/Image
    jpeg_quality: int = 85
    sensor_offset: float = 0.047    # s: the sensor/drive clock runs this far ahead of the camera's
    sensor_jitter: float = 0.002    # s: std of the stretch header stamps' jitter (clipped at 3 std)
    dropped: int = 5                # camera frames dropped (never the first or last 10)
    blur: float = 1.2               # px: Gaussian blur of the camera
    light_noise: float = 0.04       # relative std of each frame's overall brightness (lighting flicker)
    pixel_noise: float = 4.0        # std of per-pixel noise, in 0..255 units
    sensor_header: bool = True      # False: stretch as std_msgs/msg/Float32MultiArray (no header)
    # The scene, for logs unlike the default one (an importer must not depend on an orange arm on blue-green):
    arm_rgb: tuple[int, int, int] = (215, 95, 35)      # the arm's colour (lit from the top left)
    scene_rgb: tuple[int, int, int] = (98, 128, 126)   # the background's mean colour
    texture: float = 1.0            # the background's texture (blotches, stripes, blobs), 0: flat
    lighting_drift: float = 0.0     # the light's overall level drifts from 1 - this to 1 + this over the run
    motion_blur: float = 0.0        # s: exposure time; the arm moving within it is smeared (0: a sharp arm)
    distractor: bool = False        # a second object (a dark disc on a string) swinging across the scene
    start: float = 1_700_000_000.0  # s: ROS time of the recording's t = 0
    seed: int = 0


def parse_rgb(text: str, option: str) -> tuple[int, int, int]:
    """'R,G,B' -> a colour, three integers 0..255."""
    try:
        r, g, b = (int(v) for v in text.split(","))
    except ValueError:
        raise ConfigError(f"{option} {text!r}: give R,G,B, three integers 0..255, e.g. 40,40,60") from None
    if not all(0 <= v <= 255 for v in (r, g, b)):
        raise ConfigError(f"{option} {text!r}: give R,G,B, three integers 0..255, e.g. 40,40,60")
    return r, g, b


def ros_header(stamp_ns: int, frame_id: str) -> dict[str, Any]:
    """A std_msgs/Header as mcap_ros2's writer takes it: builtin_interfaces/Time split into sec and nanosec."""
    return {"stamp": {"sec": int(stamp_ns // 1_000_000_000), "nanosec": int(stamp_ns % 1_000_000_000)},
            "frame_id": frame_id}
