"""`softarm import`: a robot's ROS 2 / Foxglove MCAP log made into a softarm recording (docs/recording.md,
Imported recordings) that training, replay and the streamer read like a simulated one."""

import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np

from softarm import limits
from softarm.errors import ConfigError, RecordingError
from softarm.files import check_outputs, claimed, fingerprint, made_folders
from softarm.interrupt import Escalated, Interrupted, Stopped, stop_on_signal
from softarm.real.align import Grid, camera_period, dropped_frames, estimate_lag, frame_grid, interpolate, rate
from softarm.real.camera import CameraReader, Masks
from softarm.real.formats import log_inputs, open_log
from softarm.real.log import LogFile
from softarm.real.pool import segmenting_pool
from softarm.real.settings import ImportSettings
from softarm.real.signals import Series, SeriesReader
from softarm.real.write import write_imported

PathLike = Union[str, Path]
LAG_STEP = 0.02  # s between the lags the coarse search tries
MIN_FIT = 0.1    # R^2 below which no lag is trusted


@dataclass(frozen=True)
class ImportReport:
    path: Path
    frames: int
    seconds: float
    camera_hz: float
    sensor_hz: float
    drive_hz: Optional[float]
    frame_dt: float
    lag: float
    lag_estimated: bool
    lag_fit: Optional[float]      # R^2 of the sensors against the mask at the lag found
    gaps: list[int]               # frames without a camera image: training skips them, scoring ignores them
    dropped: int                  # camera frames missing from the camera's own stream (intervals of 2 periods or more)
    overlap: tuple[float, float]  # s on the camera's clock, relative to its first frame
    threshold: Optional[float]
    coverage: float               # mean share of the camera's pixels that are arm
    rule: str                     # the mask rule applied (for `auto`, the colour cut it fitted, else the rule it chose)
    separability: Optional[float]  # Otsu's separability of the rule `auto` chose (None for a rule given)
    auto_rule: Optional[str]      # the Otsu rule `auto` chose, whose classes the colour cut was fitted to
    pixels_per_metre: Optional[float]  # of the recording's frames (from --scale or --arm-length; None: unknown)

    def to_dict(self) -> dict[str, Any]:
        return {k: (str(v) if isinstance(v, Path) else v) for k, v in self.__dict__.items()}


def import_log(log_path: PathLike, out: PathLike, settings: ImportSettings, force: bool = False,
               progress: Callable[[int], None] = lambda n: None) -> ImportReport:
    """Convert; refuse, before writing anything, topics the log lacks, unsupported encodings, signals that do not
    overlap in time and a mask that is empty everywhere."""
    log_path, out = Path(log_path), Path(out)
    check_outputs([out], force=force, inputs=[*log_inputs(log_path), *settings.input_files()])
    try:
        with stop_on_signal() as caught, made_folders([out]), claimed([out]):  # a second import to `out`: refused
            return _import(log_path, out, settings, progress, lambda: bool(caught))
    except Stopped:  # while the log was read: the recording is written whole at the end, so nothing was
        raise Interrupted(f"nothing was written to {out}") from None
    except Escalated:
        raise Escalated(f"stopped at once by a second stop request; nothing was written to {out}") from None


def _import(log_path: Path, out: Path, settings: ImportSettings, progress: Callable[[int], None],
            stop: Callable[[], bool]) -> ImportReport:
    camera, masks, sensors, drive, digest = _read(log_path, settings, progress, stop)
    if stop():
        raise Stopped()
    coverage = float(masks.masks.mean())
    if coverage == 0:
        raise RecordingError(f"the mask is empty in every frame with --mask {settings.mask}"
                             + _suggestion(camera.threshold) + "; preview it with --preview out.png")
    lag, fit = (settings.lag, None) if settings.lag is not None else _lag(masks, sensors, settings)
    dt = settings.frame_dt or camera_period(masks.stamps)
    if not np.isfinite(dt):
        raise RecordingError(f"{settings.camera}: its frames have fewer than two distinct stamps, so it has no "
                             "rate of its own; give --frame-dt in seconds")
    grid, overlap = _grid(masks, sensors, drive, lag, dt)
    stretch = interpolate(grid.times + lag, sensors.stamps, sensors.values)
    command = interpolate(grid.times + lag, drive.stamps, drive.values)[:, 0] if drive is not None else None
    frames = np.where(grid.camera[:, None, None] >= 0, masks.masks[np.maximum(grid.camera, 0)], 0).astype(np.uint8)
    report = ImportReport(out, len(grid.times), float(grid.times[-1] - grid.times[0]), 1 / camera_period(masks.stamps),
                          rate(sensors.stamps), rate(drive.stamps) if drive is not None else None, dt, lag,
                          settings.lag is None, fit, grid.gaps.tolist(), dropped_frames(masks.stamps), overlap,
                          camera.threshold, coverage, camera.rule.text, camera.separability, camera.chosen,
                          frame_scale(masks, settings))
    source = {"log": str(log_path), "sha256": digest, "settings": settings.to_dict(),
              "found": report.to_dict() | {"t0": float(grid.times[0]), "camera_size": list(masks.size),
                                           "header_stamps": {"camera": masks.header_stamps,
                                                             "sensors": sensors.header_stamps}}}
    write_imported(out, grid.times - grid.times[0], dt, frames, grid.camera >= 0, stretch, command, sensors.names,
                   settings, source)
    return report


def _read(log_path: Path, settings: ImportSettings, progress: Callable[[int], None], stop: Callable[[], bool]
          ) -> tuple[CameraReader, Masks, Series, Optional[Series], str]:
    """The log read: its masks, sensors and drive, and its fingerprint (hashed by the pool beside the reading)."""
    with open_log(log_path) as log:
        check_camera(log, settings)
        if settings.frame_dt is not None:  # before any frame is read: the grid the log's span makes must fit
            check_grid(log.seconds(), settings.frame_dt, settings.width * settings.height + 64)
        camera = CameraReader(log, settings)
        camera.first_look(camera.samples())
        readers = [SeriesReader(log, settings.sensors, "--sensors")]
        if settings.drive:
            readers.append(SeriesReader(log, settings.drive, "--drive"))
        with segmenting_pool(camera, log.decoder(settings.camera)) as pool:
            digest = pool.submit(fingerprint, log_path)
            masks = camera.masks(pool, progress, {topic: _fan_out([r for r in readers if r.topic == topic])
                                                  for topic in {r.topic for r in readers}}, stop)
            digest = digest.result()
        sensors, drive = readers[0].series(), readers[1].series() if len(readers) > 1 else None
    if drive is not None and drive.values.shape[1] != 1:
        raise RecordingError(f"--drive {settings.drive}: holds {drive.values.shape[1]} values a message; the drive is "
                             "one command: name one element, e.g. position[0]")
    return camera, masks, sensors, drive, digest


def _fan_out(readers: list[SeriesReader]) -> Callable[[int, object], None]:
    """One topic's messages to every reader of a field of it."""
    def add(log_time: int, message: object) -> None:
        for reader in readers:
            reader.add(log_time, message)
    return add


def check_camera(log: LogFile, settings: ImportSettings) -> None:
    topic = log.topics.get(settings.camera)
    if topic is None:
        raise RecordingError(f"--camera: topic {settings.camera} is not in {log.path}; it has {log.describe()}")
    if not topic.image:
        raise RecordingError(f"--camera: {settings.camera} carries {topic.schema or 'schemaless'} messages, not "
                             f"images; {log.describe()}")
    if topic.encoding not in ("cdr", "ros1", "protobuf"):
        raise RecordingError(f"--camera: {settings.camera} holds {topic.encoding}-encoded images; softarm reads "
                             "images as ROS 2 (cdr), ROS 1 or protobuf messages")
    if topic.messages < 2:
        raise RecordingError(f"--camera: {settings.camera} holds {topic.messages} image(s); "
                             f"a recording needs two or more")


def frame_scale(masks: Masks, settings: ImportSettings) -> Optional[float]:
    """Pixels per metre of the recording's frames: the camera's own (`--scale`) times the shrink from the region of
    interest to the frames (the geometric mean of the two axes'), or the arm's extent down the frames over its
    hanging length (`--arm-length`: the 90th percentile over the frames of the rows from its top to its lowest
    pixel, as the arm hanging straight spans them). None without either: tip errors in mm are then unknown."""
    if settings.scale is not None:
        w, h = (settings.roi[2], settings.roi[3]) if settings.roi is not None else masks.size
        return settings.scale * float(np.sqrt(settings.width / w * settings.height / h))
    if settings.arm_length is not None:
        rows = masks.masks.any(axis=2)
        spans = [int(np.flatnonzero(r)[-1] - np.flatnonzero(r)[0] + 1) for r in rows if r.any()]
        if not spans:
            raise RecordingError("--arm-length: the mask is empty in every frame, so the arm's length cannot be read")
        return float(np.percentile(spans, 90)) / settings.arm_length
    return None


def _suggestion(threshold: Optional[float]) -> str:
    if threshold is not None:
        return f" (Otsu's threshold came out at {threshold:.0f}: try the other side, e.g. < instead of >)"
    return "; try a lower threshold, or Otsu's (e.g. --mask s>otsu)"


def _lag(masks: Masks, sensors: Series, settings: ImportSettings) -> tuple[float, float]:
    try:
        found = estimate_lag(masks.stamps, masks.masks, sensors.stamps, sensors.values, settings.max_lag, LAG_STEP)
    except ValueError as e:
        raise RecordingError(f"the lag between camera and sensors cannot be found: {e}; give it with --lag (or a "
                             "smaller --max-lag)") from None
    if found.fit < MIN_FIT:
        raise RecordingError(f"the lag between camera and sensors cannot be found: at the best lag, "
                             f"{found.lag * 1e3:+.0f} ms, the masks explain {found.fit:.0%} of the sensors' variance; "
                             "check the topics and the mask (--preview), or give --lag")
    if found.rival is not None:
        warnings.warn(f"the motion is nearly periodic: a lag of {found.rival * 1e3:+.0f} ms fits almost as well as the "
                      f"{found.lag * 1e3:+.0f} ms found; if the clocks may be that far apart, check it and give --lag",
                      stacklevel=3)
    return found.lag, found.fit


def check_grid(seconds: float, dt: float, frame_bytes: int) -> None:
    """Refuse a grid of `seconds` at `dt` whose frames (`frame_bytes` each: the mask, the signals) the memory cannot
    hold, before it is made."""
    most = limits.fitting(frame_bytes)
    if seconds / dt > most:
        raise ConfigError(f"--frame-dt {dt:g} s makes {seconds / dt:.3g} frames of {seconds:.3g} s of log, more than "
                          f"the memory holds (at most {most:,}): give a longer --frame-dt")


def _grid(masks: Masks, sensors: Series, drive: Optional[Series], lag: float,
          dt: float) -> tuple[Grid, tuple[float, float]]:
    """The frame grid over the time every signal covers (the sensors' and drive's stamps less the lag)."""
    spans = [(masks.stamps[0], masks.stamps[-1], "camera"),
             (sensors.stamps[0] - lag, sensors.stamps[-1] - lag, "sensors")]
    if drive is not None:
        spans.append((drive.stamps[0] - lag, drive.stamps[-1] - lag, "drive"))
    start, end = max(s[0] for s in spans), min(s[1] for s in spans)
    if end - start < 2 * dt:
        covered = "; ".join(f"{name} {a - masks.stamps[0]:.3f}..{b - masks.stamps[0]:.3f} s" for a, b, name in spans)
        raise RecordingError(f"camera and sensors share no time (after a lag of {lag:.3f} s): {covered}, on the "
                             "camera's clock from its first frame; check the topics, or give --lag")
    check_grid(end - start, dt, masks.masks[0].size + 8 * (2 + sensors.values.shape[1] + (drive is not None)))
    grid = frame_grid(masks.stamps, start, end, dt)
    return grid, (float(start - masks.stamps[0]), float(end - masks.stamps[0]))
