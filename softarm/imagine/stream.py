"""Imagination online: one input sample in, one imagined frame out, at a robot's control rate.

A robot's loop calls `step(sample)` once per reading (every 10 ms at the default frame rate). The latent
model's online reader keeps what it needs (the window model its last `history` samples, a stream model
only its recurrent state; an ensemble one reader per member) and answers; the decoder, prepared for one code
at a time (`FrameDecoder`), then draws it; the surprise's forward model compares the sample with what the
samples before it expected: the same computation as a batch replay, frame for frame. With the paper's set-up
(`include_current` false) the samples up to k imagine frame k+1, what the body will look like at the next
sample; with `include_current` frame k.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Union

import numpy as np

from softarm.model.prediction import Prediction, joined_members

if TYPE_CHECKING:
    from softarm.imagine.imaginer import Imaginer


@dataclass(frozen=True)
class ImaginedFrame:
    frame: int                  # the frame index imagined
    probabilities: np.ndarray   # (H, W) pixel probabilities
    confidence: float           # in (0, 1]: how far to trust it (the checkpoint's `train.confidence`)
    surprise: float = float("nan")  # what the sample felt beyond what the command predicted (~1 undisturbed)
    alarm: bool = False             # the surprise is above the checkpoint's alarm threshold


class StreamingImaginer:
    @classmethod
    def from_checkpoint(cls, path: Union[str, Path],
                        sensor_noise: Optional[dict[str, Any]] = None) -> "StreamingImaginer":
        """The streamer of a checkpoint written by `softarm train`, for sensors with the imperfections it was
        trained with, or those of `sensor_noise` (keys of [sensing] but pairs: `{"noise": 2e-5}`), which its
        surprise then expects (as replay's `--sensor-noise` does)."""
        from softarm.imagine.trained import TrainedModel  # torch loads here, not when softarm is imported

        model = TrainedModel(path)
        return cls(model.imaginer_for(model.with_sensors(sensor_noise)))

    def __init__(self, imaginer: "Imaginer"):
        from softarm.model.frame_decoder import FrameDecoder  # torch loads here, not when softarm is imported

        self.imaginer = imaginer
        self._draw = FrameDecoder(imaginer.autoencoder)
        self.reset()

    def step(self, sample: Optional[np.ndarray] = None, **channels: Any) -> Optional[ImaginedFrame]:
        """Take the next sample: every input channel's raw readings side by side in the checkpoint's order
        (`sample`), or each channel by its name (`step(stretch=[...], drive=0.002)`, the stretch in m and the
        drive's displacement in m). Return the frame it lets the model imagine, or None until `history` samples
        have been seen (the first frame a batch replay imagines). A sample holding NaN or an infinity (a sensor that
        dropped out) is refused with a ValueError before it touches anything: the streamer stays as it was, so the
        caller may give the next good sample (or the last good one again), or `reset()` after a long gap."""
        imaginer = self.imaginer
        raw = np.asarray(sample if sample is not None else self.assemble(channels), np.float64)
        if raw.shape != (imaginer.inputs.features,):
            raise ValueError(
                f"a sample holds {imaginer.inputs.features} readings "
                f"({', '.join(f'{c.name}: {w}' for c, w in zip(imaginer.inputs.channels, imaginer.inputs.widths))}), "
                f"got shape {raw.shape}")
        if not np.isfinite(raw).all():
            bad = int(np.flatnonzero(~np.isfinite(raw))[0])
            raise ValueError(f"reading {bad} of the sample is {raw[bad]}: readings must be finite (this sample was not "
                             "taken; give the next one, or reset() after a gap)")
        self.samples += 1
        exact = imaginer.inputs.normalise(raw)  # float64: the ridge baseline's window, as a batch replay reads it
        normalised = exact.astype(np.float32)  # `imaginer.normalised`: what the networks read
        if imaginer.ridge is not None:
            self._window[:-1] = self._window[1:]
            self._window[-1] = exact
        answers = [reader.step(normalised) for reader in self._readers]
        surprise, residual = ((float("nan"), float("nan")) if self._surprise is None
                              else self._surprise.step(normalised.astype(np.float64), self._readers[0].state_vector))
        if answers[0] is None:
            return None
        target = np.array([self.samples - 1 + imaginer.latent.lead])
        prediction = joined_members([Prediction(target, latent[None], log_error[None])
                                     for latent, log_error in answers])
        if imaginer.ridge is not None:
            prediction = prediction.with_ridge_gap(imaginer.ridge_latents(self._window[None]))
        if imaginer.surprise is not None:  # the calibrated confidence reads both, as in a batch replay
            prediction = prediction.with_surprise(np.array([surprise]), np.array([residual]))
        drawn = self._draw(imaginer.latent_scaler.inverse(prediction.latents)[0])
        confidence = float(imaginer.confidence(prediction.with_picture(drawn[None]))[0])  # it reads the picture too
        return ImaginedFrame(int(target[0]), drawn, confidence, surprise,
                             bool(imaginer.surprise is not None and surprise > imaginer.surprise.threshold))

    def assemble(self, channels: dict[str, Any]) -> np.ndarray:
        """One sample from readings named by channel, in the checkpoint's order."""
        names = [c.name for c in self.imaginer.inputs.channels]
        if sorted(channels) != sorted(names):
            raise ValueError(f"this model reads {', '.join(names)}; got {', '.join(sorted(channels)) or 'none'}")
        return np.concatenate([np.atleast_1d(np.asarray(channels[name], np.float64)) for name in names])

    def reset(self) -> None:
        """Forget what was read (a new run or a gap in the readings)."""
        imaginer = self.imaginer
        self._readers = [model.online() for model in (imaginer.latent, *imaginer.members)]
        self._surprise = imaginer.surprise.online() if imaginer.surprise is not None else None
        self.samples = 0  # samples seen so far; the latest one is sample samples - 1
        self._window = np.zeros((imaginer.latent.history, imaginer.inputs.features))  # the last samples, oldest first

