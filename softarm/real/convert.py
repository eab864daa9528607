"""`softarm import`: a robot's ROS 2 / Foxglove MCAP log made into a softarm recording (docs/recording.md,
Imported recordings) that training, replay and the streamer read like a simulated one."""

import warnings
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np

from softarm.errors import RecordingError
from softarm.files import check_outputs, claimed, fingerprint, made_folders
from softarm.real.align import Grid, camera_period, dropped_frames, estimate_lag, frame_grid, interpolate, rate
from softarm.real.camera import CameraReader, Masks
from softarm.real.log import LogFile
from softarm.real.settings import ImportSettings
from softarm.real.signals import Series, SeriesReader
from softarm.real.write import write_imported

PathLike = Union[str, Path]
LAG_STEP = 0.02  # s between the lags the coarse search tries


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

    def to_dict(self) -> dict[str, Any]:
        return {k: (str(v) if isinstance(v, Path) else v) for k, v in self.__dict__.items()}


def import_log(log_path: PathLike, out: PathLike, settings: ImportSettings, force: bool = False,
               progress: Callable[[int], None] = lambda n: None) -> ImportReport:
    """Convert; refuse, before writing anything, topics the log lacks, unsupported encodings, signals that do not
    overlap in time and a mask that is empty everywhere."""
    log_path, out = Path(log_path), Path(out)
    check_outputs([out], force=force, inputs=[log_path])
    with LogFile(log_path) as log, ThreadPoolExecutor(1) as hashing:
        check_camera(log, settings)
        digest = hashing.submit(fingerprint, log_path)  # hashlib releases the GIL: it reads while the log is read
        camera = CameraReader(log, settings)
        camera.first_look(camera.samples())
        readers = [SeriesReader(log, settings.sensors, "--sensors")]
        if settings.drive:
            readers.append(SeriesReader(log, settings.drive, "--drive"))
        masks = camera.masks(progress, {topic: _fan_out([r for r in readers if r.topic == topic])
                                        for topic in {r.topic for r in readers}})
        sensors, drive = readers[0].series(), readers[1].series() if len(readers) > 1 else None
    coverage = float(masks.masks.mean())
    if coverage == 0:
        raise RecordingError(f"the mask is empty in every frame with --mask {settings.mask}"
                             + _suggestion(camera.threshold) + "; preview it with --preview out.png")
    lag, fit = (settings.lag, None) if settings.lag is not None else _lag(masks, sensors, settings)
    dt = settings.frame_dt or camera_period(masks.stamps)
    grid, overlap = _grid(masks, sensors, drive, lag, dt)
    stretch = interpolate(grid.times + lag, sensors.stamps, sensors.values)
    command = interpolate(grid.times + lag, drive.stamps, drive.values)[:, 0] if drive is not None else None
    frames = np.where(grid.camera[:, None, None] >= 0, masks.masks[np.maximum(grid.camera, 0)], 0).astype(np.uint8)
    report = ImportReport(out, len(grid.times), float(grid.times[-1] - grid.times[0]), 1 / camera_period(masks.stamps),
                          rate(sensors.stamps), rate(drive.stamps) if drive is not None else None, dt, lag,
                          settings.lag is None, fit, grid.gaps.tolist(), dropped_frames(masks.stamps), overlap,
                          camera.threshold, coverage)
    source = {"log": str(log_path), "sha256": digest.result(), "settings": settings.to_dict(),
              "found": report.to_dict() | {"t0": float(grid.times[0]), "camera_size": list(masks.size),
                                           "header_stamps": {"camera": masks.header_stamps,
                                                             "sensors": sensors.header_stamps}}}
    with made_folders([out]), claimed([out]):
        write_imported(out, grid.times - grid.times[0], dt, frames, grid.camera >= 0, stretch, command, sensors.names,
                       settings, source)
    return report


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


def _suggestion(threshold: Optional[float]) -> str:
    if threshold is not None:
        return f" (Otsu's threshold came out at {threshold:.0f}: try the other side, e.g. < instead of >)"
    return "; try a lower threshold, or Otsu's (e.g. --mask s>otsu)"


def _lag(masks: Masks, sensors: Series, settings: ImportSettings) -> tuple[float, float]:
    try:
        found = estimate_lag(masks.stamps, masks.masks, sensors.stamps, sensors.values, settings.max_lag, LAG_STEP)
    except ValueError:
        raise RecordingError(f"too few camera frames lie within the sensors' time, +-{settings.max_lag:g} s, to find "
                             "the lag: give it with --lag, or a smaller --max-lag") from None
    if found.rival is not None:
        warnings.warn(f"the motion is nearly periodic: a lag of {found.rival * 1e3:+.0f} ms fits almost as well as the "
                      f"{found.lag * 1e3:+.0f} ms found; if the clocks may be that far apart, check it and give --lag",
                      stacklevel=3)
    return found.lag, found.fit


def _grid(masks: Masks, sensors: Series, drive: Optional[Series], lag: float, dt: float) -> tuple[Grid, tuple[float, float]]:
    """The frame grid over the time every signal covers (the sensors' and drive's stamps less the lag)."""
    spans = [(masks.stamps[0], masks.stamps[-1], "camera"), (sensors.stamps[0] - lag, sensors.stamps[-1] - lag, "sensors")]
    if drive is not None:
        spans.append((drive.stamps[0] - lag, drive.stamps[-1] - lag, "drive"))
    start, end = max(s[0] for s in spans), min(s[1] for s in spans)
    if end - start < 2 * dt:
        covered = "; ".join(f"{name} {a - masks.stamps[0]:.3f}..{b - masks.stamps[0]:.3f} s" for a, b, name in spans)
        raise RecordingError(f"camera and sensors share no time (after a lag of {lag:.3f} s): {covered}, on the "
                             "camera's clock from its first frame; check the topics, or give --lag")
    grid = frame_grid(masks.stamps, start, end, dt)
    return grid, (float(start - masks.stamps[0]), float(end - masks.stamps[0]))
