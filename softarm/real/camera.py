"""The camera topic of a log as masks at the models' camera size, read frame by frame (never all decoded at
once): a first look at a few frames fixes what the whole recording shares (the background, Otsu's threshold),
then every frame is decoded, cut to the region of interest, segmented and area-averaged down."""

import warnings
from collections import deque
from concurrent.futures import Executor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional, Sequence

import numpy as np

from softarm.errors import ConfigError, RecordingError
from softarm.interrupt import Stopped
from softarm.real.fields import header_stamp
from softarm.real.images import crop_box, decode_image
from softarm.real.log import LogFile
from softarm.real.pool import segment_task
from softarm.real.segment import (
    BACKGROUND_CHANNELS,
    SEPARABLE,
    Auto,
    MaskRule,
    choose_rule,
    downsample,
    fit_colour,
    main_parts,
    otsu,
    parse_mask,
)
from softarm.real.settings import ImportSettings

Other = dict[str, Callable[[int, object], None]]
SAMPLES = 40  # frames the first look decodes
TASK = 16       # camera frames a worker segments per task
IN_FLIGHT = 16  # tasks queued at a time
SUPERSAMPLE = 1.5  # image pixels per camera pixel (each way) that a JPEG is decoded with, at least


@dataclass(frozen=True)
class Masks:
    stamps: np.ndarray      # (N,) s, the camera's (header stamps, or log times where it has none)
    masks: np.ndarray       # (N, H, W) uint8 0/1 at the models' camera size
    header_stamps: bool
    size: tuple[int, int]   # the camera's own (width, height)


class CameraReader:
    def __init__(self, log: LogFile, settings: ImportSettings):
        self.log, self.settings = log, settings
        self.rule: MaskRule = parse_mask(settings.mask)
        self.where = f"{log.path}:{settings.camera}"
        self.background: Optional[np.ndarray] = None
        self.threshold: Optional[float] = None
        self.separability: Optional[float] = None  # of the rule `auto` chose
        self.chosen: Optional[str] = None          # the Otsu rule `auto` chose (its colour cut is then applied)
        self.clean = isinstance(self.rule, Auto)   # keep only the mask's main parts

    def decode(self, message: object) -> tuple[object, np.ndarray, tuple[int, int]]:
        """(message, ROI pixels, camera size) of one decoded image message."""
        pixels, size = decode_image(message, self.where, self._least_scale, self.settings.roi)
        return message, pixels, size

    def _least_scale(self, size: tuple[int, int]) -> float:
        """The smallest decoding scale that keeps SUPERSAMPLE image pixels per camera pixel across the ROI."""
        s = self.settings
        w, h = (s.roi[2], s.roi[3]) if s.roi is not None else size
        return SUPERSAMPLE * max(s.width / max(w, 1), s.height / max(h, 1))

    def first_look(self, messages: Sequence[object]) -> None:
        """The background (median of frames across the log, or an image file) and Otsu's threshold, from a few
        image messages spread over the log."""
        background = self.settings.background
        decoded = [self.decode(message) for message in messages]
        if not decoded:
            raise RecordingError(f"{self.where} holds no image")
        shape = tuple(min(p.shape[i] for _, p, _ in decoded) for i in (0, 1))
        samples = [p[:shape[0], :shape[1]] for _, p, _ in decoded]
        if background == "median":
            self.background = np.median(np.stack(samples), axis=0).astype(np.int16)
        elif background is not None:
            self.background = _background_file(Path(background), shape, decoded[0][2], self.settings.roi)
        if isinstance(self.rule, Auto):
            seed, self.threshold, self.separability = choose_rule(samples, self.background)
            if self.separability < SEPARABLE:
                warnings.warn(f"{self.where}: no mask rule separates the arm well (the best, {seed.text}, scores "
                              f"{self.separability:.2f} of 1); look at --preview PNG and give --mask or --roi",
                              stacklevel=2)
            colour = None if seed.name in BACKGROUND_CHANNELS else fit_colour(samples, seed, self.threshold)
            self.rule, self.chosen = colour or seed, seed.text
        elif self.rule.needs_otsu:
            self.threshold = otsu(np.concatenate([self.rule.channel(p, self.background).ravel() for p in samples]))

    def samples(self) -> list[object]:
        """SAMPLES image messages spread over the log, decoded as messages (not yet as pixels): the first look's."""
        return self.log.spread(self.settings.camera, SAMPLES)

    def masks(self, pool: Executor, progress: Callable[[int], None] = lambda n: None,
              others: Optional[Other] = None, stop: Callable[[], bool] = lambda: False) -> Masks:
        """Every frame's mask and stamp, in the log's order. Frames are decoded and segmented in the `pool`
        (`pool.segmenting_pool`, a worker process per core), TASK frames a task and at most IN_FLIGHT tasks at a
        time, while this process reads the log and hands the messages of other topics to `others` (topic -> a
        callback of log time and message). `stop()` is asked between tasks: True raises Stopped."""
        done: list[tuple[float, bool, np.ndarray, tuple[int, int]]] = []
        others, task, pending = others or {}, [], deque()
        try:
            for topic, log_time, data, decode in self.log.raw(self.settings.camera, *others):
                if topic != self.settings.camera:
                    others[topic](log_time, decode(data))
                    continue
                task.append((log_time, data))
                if len(task) == TASK:
                    if stop():
                        raise Stopped()
                    pending.append(pool.submit(segment_task, task))
                    task = []
                while len(pending) > IN_FLIGHT or (pending and pending[0].done()):
                    done.extend(pending.popleft().result())
                    progress(len(done))
            pending.append(pool.submit(segment_task, task))
            while pending:
                done.extend(pending.popleft().result())
        except BrokenProcessPool:
            raise RecordingError("a process segmenting camera frames died (out of memory?); nothing was written"
                                 ) from None
        if not done:
            raise RecordingError(f"{self.where} holds no image")
        stamps, headers, masks, sizes = zip(*done)
        if not all(headers):
            warnings.warn(f"{self.where}: images without a header stamp are placed at their log time (when the "
                          "log received them), which lags acquisition by an unknown, varying transport delay",
                          stacklevel=2)
        order = np.argsort(stamps, kind="stable")
        if len(set(sizes)) > 1:
            raise RecordingError(f"{self.where}: the camera's frames change size ({sorted(sizes)}); import each part "
                                 "of the log apart")
        return Masks(np.asarray(stamps)[order], np.stack(masks)[order], all(headers), sizes[0])

    def mask_of(self, log_time: int, message: object) -> tuple[float, bool, np.ndarray, tuple[int, int]]:
        """(stamp, whether it is the header's, mask, camera size) of one decoded camera message."""
        message, pixels, size = self.decode(message)
        stamp = header_stamp(message)
        return (stamp if stamp is not None else log_time * 1e-9), stamp is not None, self.segment(pixels), size

    def segment(self, pixels: np.ndarray) -> np.ndarray:
        """(height, width) uint8 0/1: the mask of one frame's ROI pixels at the models' camera size."""
        values = self.rule.channel(pixels, self._fit(self.background, pixels))
        mask = downsample(self.rule.apply(values, self.threshold), self.settings.width, self.settings.height)
        return main_parts(mask) if self.clean else mask

    def examples(self, count: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """(the whole frame with the region of interest outlined, ROI pixels, mask) of `count` frames spread over
        the log, for a preview."""
        from PIL import Image, ImageDraw  # loaded when an image is met: importing softarm stays light

        out = []
        for message in self.log.spread(self.settings.camera, count):
            rgb, size = decode_image(message, self.where, self._least_scale)
            pixels = rgb[crop_box(self.settings.roi, size, (rgb.shape[1], rgb.shape[0]))]
            framed = Image.fromarray(rgb)
            if self.settings.roi is not None:
                x, y, w, h = self.settings.roi
                fx, fy = rgb.shape[1] / size[0], rgb.shape[0] / size[1]
                ImageDraw.Draw(framed).rectangle((x * fx, y * fy, (x + w) * fx - 1, (y + h) * fy - 1),
                                                 outline=(255, 255, 0), width=2)
            out.append((np.asarray(framed), pixels, self.segment(pixels)))
        return out

    @staticmethod
    def _fit(background: Optional[np.ndarray], pixels: np.ndarray) -> Optional[np.ndarray]:
        return None if background is None else background[:pixels.shape[0], :pixels.shape[1]]


def _background_file(path: Path, shape: tuple[int, ...], camera: tuple[int, int],
                     roi: Optional[tuple[int, int, int, int]]) -> np.ndarray:
    """A background photo of the camera's own size, cut to the region of interest and scaled as frames are."""
    from PIL import Image  # loaded when an image is met: importing softarm stays light

    try:
        image = Image.open(path).convert("RGB")
    except (OSError, ValueError) as e:
        raise ConfigError(f"--background {path}: not a readable image ({e})") from None
    if image.size != camera:
        raise ConfigError(f"--background {path} is {image.size[0]}x{image.size[1]}, but the camera's frames are "
                          f"{camera[0]}x{camera[1]}: give a frame of the same camera")
    if roi is not None:
        image = image.crop((roi[0], roi[1], roi[0] + roi[2], roi[1] + roi[3]))
    return np.asarray(image.resize((shape[1], shape[0]), Image.Resampling.BOX), np.int16)
