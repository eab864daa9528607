"""What `softarm import` is asked to do: the topics, the segmentation, the grid and the lag. Written whole into
the imported recording's metadata, so the conversion can be repeated and judged."""

import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Optional

from softarm.config import load_config
from softarm.errors import ConfigError


@dataclass(frozen=True)
class ImportSettings:
    camera: str                      # image topic
    sensors: str                     # TOPIC:FIELD of the stretch (or bend) readings
    drive: Optional[str] = None      # TOPIC:FIELD of the actuator command, on the sensors' clock
    mask: str = "auto"               # segmentation rule (softarm.real.segment)
    background: Optional[str] = None  # "median" (of frames across the log) or an image file
    roi: Optional[tuple[int, int, int, int]] = None  # x, y, width, height in the camera's own pixels
    width: int = field(default_factory=lambda: load_config().camera.width)   # the camera size the models use
    height: int = field(default_factory=lambda: load_config().camera.height)
    frame_dt: Optional[float] = field(
        default_factory=lambda: load_config().integration.frame_dt)  # s; None: the camera's period
    lag: Optional[float] = None      # s the sensors' stamps run ahead of the camera's; None: estimated
    max_lag: float = 0.25            # s: the lag is searched in [-max_lag, max_lag]
    scale: Optional[float] = None    # px/m: the camera's own pixels per metre in the arm's plane
    arm_length: Optional[float] = None  # m: the arm's length as it hangs at rest, for the scale from the masks

    def __post_init__(self) -> None:
        if self.roi is not None and (len(self.roi) != 4 or min(self.roi[2:]) <= 0 or min(self.roi[:2]) < 0):
            raise ConfigError(f"--roi {self.roi}: give X,Y,WIDTH,HEIGHT in pixels, width and height positive")
        if self.frame_dt is not None and not (math.isfinite(self.frame_dt) and 0 < self.frame_dt < 10):
            raise ConfigError(f"--frame-dt {self.frame_dt}: give a period in seconds, above 0")
        if self.lag is not None and not (math.isfinite(self.lag) and abs(self.lag) <= 3600):
            raise ConfigError(f"--lag {self.lag}: give the clocks' offset in seconds, a finite number")
        if not 0 < self.max_lag <= 60:
            raise ConfigError(f"--max-lag {self.max_lag}: give a search range in seconds, above 0 and at most 60")
        for option, value in (("--scale", self.scale), ("--arm-length", self.arm_length)):
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ConfigError(f"{option} {value}: "
                                  f"give a positive number ({'px/m' if option == '--scale' else 'm'})")
        if self.scale is not None and self.arm_length is not None:
            raise ConfigError("--scale and --arm-length both give the camera's scale: give one")
        if not (0 < self.width <= 4096 and 0 < self.height <= 4096):
            raise ConfigError(f"camera size {self.width}x{self.height} is out of range")

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def input_files(self) -> list[Path]:
        """The files these settings read besides the log (a background image): inputs no output may replace."""
        return [Path(self.background)] if self.background not in (None, "median") else []


def parse_frame_dt(text: Optional[str]) -> Optional[float]:
    """'camera' -> None (the camera's own period), a number -> seconds, nothing -> the config's frame_dt."""
    if text is None:
        return load_config().integration.frame_dt
    if text.strip().lower() == "camera":
        return None
    try:
        return float(text)
    except ValueError:
        raise ConfigError(f"--frame-dt {text!r}: give a period in seconds, or 'camera' for the camera's own") from None


def parse_roi(text: Optional[str]) -> Optional[tuple[int, int, int, int]]:
    """'X,Y,W,H' -> a region of interest in pixels."""
    if text is None:
        return None
    try:
        x, y, w, h = (int(v) for v in text.split(","))
    except ValueError:
        raise ConfigError(f"--roi {text!r}: give X,Y,WIDTH,HEIGHT in whole pixels, e.g. 26,58,588,364") from None
    return x, y, w, h
