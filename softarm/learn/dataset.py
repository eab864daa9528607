"""Learning data from recordings: frames and the model's raw inputs, split by time as in the paper.

Each recording is split on its own: the first `train_fraction` of its frames train, the next
`test_fraction` test the autoencoder (and validate the latent model), the rest is the imagination segment.
Input windows never straddle a split, so no test target is predicted from training samples. A
corpus also keeps whole recordings out (`validation_recordings`): their test segment starts at their
first frame, so validation covers motions the networks never saw.
"""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional, Sequence, Union

import numpy as np

from softarm.arm.drive import HELD_OUT_SEED_BASE
from softarm.config import Config, TrainConfig
from softarm.corpus.manifest import MIN_CORPUS, motion_group
from softarm.errors import RecordingError
from softarm.files import fingerprint
from softarm.interrupt import Stopped
from softarm.learn.packed_frames import PackedFrames
from softarm.model.fits import check_fits, recording_shape
from softarm.model.input_windows import input_windows, window_count
from softarm.model.inputs import InputChannel, read_channels
from softarm.record.reader import read_recording


@dataclass(frozen=True)
class RunData:
    """One recording's learning arrays."""
    name: str
    fingerprint: str            # sha256 of the file, first 16 hex digits
    frames: PackedFrames        # (T, H, W) 0/1, eight pixels to a byte
    inputs: np.ndarray          # (T, F) float32, every input channel side by side, raw (SI units)
    times: np.ndarray           # (T,) s
    bounds: tuple[int, int]     # train = [0, b0), test = [b0, b1), imagine = [b1, T)
    held_out: bool = False      # a validation recording: nothing of it trains (b0 = 0)
    positions: Optional[np.ndarray] = None  # (T, N, 2) float32 node positions (m), where the recording has them
    seen: Optional[np.ndarray] = None  # (T,) bool: frames the camera has (None: all); gaps train and score nothing
    calm: Optional[np.ndarray] = None  # (T,) bool: no disturbance acts (None: none ever does)
    group: str = ""             # its corpus's motion group ("": none listed it)

    def segment(self, name: str) -> tuple[int, int]:
        b0, b1 = self.bounds
        return {"train": (0, b0), "test": (b0, b1), "imagine": (b1, len(self.times))}[name]


@dataclass(frozen=True)
class Dataset:
    sequences: list[RunData]
    channels: tuple[InputChannel, ...]
    widths: list[int]              # features of each channel
    pixels_per_metre: float = float("nan")  # the cameras' scale for tip errors in mm (NaN: not known for all)
    _segments: dict[str, PackedFrames] = field(default_factory=dict, repr=False, compare=False)

    @property
    def image_shape(self) -> tuple[int, int]:
        return self.sequences[0].frames.shape[1:]

    def frames(self, segment: str) -> PackedFrames:
        """(M, H, W) frames of a segment, all recordings in order, packed: joined once."""
        if segment not in self._segments:
            parts = [s.frames.select(slice(*s.segment(segment))) for s in self.sequences]
            if any(s.seen is not None for s in self.sequences):  # a camera's gaps are no training or test frames
                parts = [p if s.seen is None else p.select(s.seen[slice(*s.segment(segment))])
                         for p, s in zip(parts, self.sequences)]
            self._segments[segment] = PackedFrames.join(parts)
        return self._segments[segment]

    def windows(self, segment: str, history: int, lead: int) -> tuple[np.ndarray, np.ndarray]:
        """Raw input windows (M, history, F) of a segment, all recordings, and the (recording, frame) each
        imagines (M, 2)."""
        inputs, targets = [], []
        for n, seq in enumerate(self.sequences):
            start, end = seq.segment(segment)
            w, k = input_windows(seq.inputs, history, lead, start, end)
            inputs.append(w)
            targets.append(np.stack([np.full(len(k), n), k], axis=1))
        if not sum(map(len, inputs)):
            raise RecordingError(f"the {segment} segment is shorter than a history of {history} samples")
        return np.concatenate(inputs), np.concatenate(targets)

    def seen(self, targets: np.ndarray) -> np.ndarray:
        """(M,) bool: which (recording, frame) targets (M, 2) the camera has, so that scores ignore its gaps."""
        out = np.ones(len(targets), bool)
        for n, seq in enumerate(self.sequences):
            if seq.seen is not None:
                chosen = targets[:, 0] == n
                out[chosen] = seq.seen[targets[chosen, 1]]
        return out

    def seen_frames(self, segment: str) -> np.ndarray:
        """(M,) bool over every frame of a segment, all recordings in order: the camera has it."""
        parts = [(s.seen, slice(*s.segment(segment))) for s in self.sequences]
        return np.concatenate([np.ones(part.stop - part.start, bool) if seen is None else seen[part]
                               for seen, part in parts])

    def count(self, segment: str) -> int:
        """Camera frames of a segment, all recordings (a camera's gaps left out, as `frames` leaves them)."""
        return int(self.seen_frames(segment).sum())

    def window_count(self, segment: str, history: int, lead: int) -> int:
        """The input windows `windows` gives for a segment, all recordings."""
        return sum(window_count(end - start, history, lead)
                   for start, end in (s.segment(segment) for s in self.sequences))

    def target_frames(self, targets: np.ndarray) -> np.ndarray:
        return np.stack([self.sequences[n].frames[k] for n, k in targets])

    def fingerprints(self) -> list[dict]:
        """Name, SHA-256 (first 16 hex digits) and frame count of each recording: what a checkpoint was trained on."""
        return [{"name": s.name, "sha256": s.fingerprint, "frames": len(s.times)} for s in self.sequences]


def split_bounds(n_frames: int, train: TrainConfig) -> tuple[int, int]:
    """Frame indices where test and imagination begin (8500 and 9500 for 10 000 frames)."""
    return round(n_frames * train.train_fraction), round(n_frames * (train.train_fraction + train.test_fraction))


def load_dataset(paths: Sequence[Union[str, Path]], config: Config, channels: Sequence[InputChannel],
                 stop: Callable[[], bool] = lambda: False,
                 progress: Callable[[int, int], None] = lambda done, total: None) -> Dataset:
    """Read recordings (all of one image shape and channel widths), each channel as `config` reads it, and
    split each by time; the frames are kept packed. `stop()` is asked before each recording: True raises
    Stopped; `progress(done, total)` hears of each one read."""
    if not paths:
        raise RecordingError("give at least one recording")
    train, channels = config.train, tuple(channels)
    sequences, first, scales = [], None, set()
    held_out = validation_indices(len(paths), train.validation_recordings)
    progress(0, len(paths))
    for path in map(Path, paths):
        if stop():
            raise Stopped()
        rec = read_recording(path, nodes=True)  # the node positions train the privileged baseline too
        if int(rec.model.get("seed", 0)) >= HELD_OUT_SEED_BASE:
            raise RecordingError(f"{path.name} was made from seed {rec.model['seed']}, one of the held-out suite's "
                                 f"(>= {HELD_OUT_SEED_BASE}): train on seeds below it")
        bounds = split_bounds(len(rec.times), train)
        validation = len(sequences) in held_out
        seq = RunData(name=path.name, fingerprint=fingerprint(path), frames=PackedFrames.pack(rec.frames),
                      inputs=read_channels(channels, rec, config).astype(np.float32), times=rec.times,
                      bounds=(0, bounds[1]) if validation else bounds, held_out=validation,
                      positions=None if rec.positions is None else rec.positions.astype(np.float32),
                      seen=rec.seen if not rec.seen.all() else None,
                      calm=~rec.active.any(axis=1) if rec.active.any() else None, group=motion_group(path))
        shape = recording_shape(rec.model, channels, config)
        if first is None:
            first = (path.name, shape)
        check_fits(seq.name, shape, first[1], channels, first[0])
        check_segments(seq, train)
        sequences.append(seq)
        scales.add(rec.pixels_per_metre if rec.imported else config.camera.pixels_per_metre)
        progress(len(sequences), len(paths))
    scale = scales.pop() if len(scales) == 1 else float("nan")  # one scale for all, or tip errors unknown
    return Dataset(sequences, channels, list(first[1][1]), scale)


def validation_indices(count: int, share: float) -> set[int]:
    """Recordings kept out of training: `share` of a corpus of more than MIN_CORPUS, evenly spaced over its
    list (which runs group by group, so they come from groups across the corpus); none of a smaller set."""
    if count <= MIN_CORPUS or share <= 0:
        return set()
    kept = max(1, round(count * share))
    return {int((i + 0.5) * count / kept) for i in range(kept)}


def check_segments(seq: RunData, train: TrainConfig) -> None:
    """Refuse before training a recording whose test or imagination segment holds no input window."""
    needed = train.history + train.lead
    for name in ("test", "imagine"):
        start, end = seq.segment(name)
        if end - start < needed:
            raise RecordingError(f"{seq.name}: its {name} segment has {end - start} frames, fewer than the "
                                 f"{needed} a history of {train.history} needs; record longer")
