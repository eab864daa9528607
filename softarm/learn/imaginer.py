"""Imagination: stretch -> latent predictor -> normalised latent -> decoder -> frame probabilities.

An `Imaginer` holds the trained networks and the training statistics; training uses it for its
metrics, `softarm replay` and `evaluate` for whole recordings and the streamer for one sample at a
time, so all of them compute imagination the same way. Whatever the model, frame k is imagined from
the samples up to k - 1 (k with `include_current`), and the first frame imagined is the first a
`history`-sample window reaches: both models answer for the same frames, beside the same baselines.
"""

from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np
import torch
from torch import nn

from softarm.learn.dataset import stretch_windows
from softarm.errors import CheckpointError, RecordingError
from softarm.learn.scaler import Scaler
from softarm.learn.models import Autoencoder, latent_model

BATCH = 256  # fastest decoding batch on a 2-core CPU
STREAMS = 64  # recordings a stream model reads side by side


@dataclass(frozen=True)
class Prediction:
    """The latent answers for some frames of one recording (or several, one after another)."""
    targets: np.ndarray     # (M,) frame indices
    latents: np.ndarray     # (M, K) normalised kept latent features
    log_error: np.ndarray   # (M, K) the model's own estimate of each feature's log squared error

    @property
    def confidence(self) -> np.ndarray:
        """(M,) in (0, 1]: 1 / (1 + the predicted mean squared error of the normalised latent); 0.5 means the
        model expects to be as far off as a guess of the mean frame's code."""
        return 1.0 / (1.0 + np.exp(self.log_error).mean(axis=1))

    def take(self, keep: np.ndarray) -> "Prediction":
        return Prediction(self.targets[keep], self.latents[keep], self.log_error[keep])


@dataclass
class Imaginer:
    autoencoder: Autoencoder
    lstm: nn.Module          # StretchToLatent ("window") or StreamToLatent ("stream")
    latent_scaler: Scaler
    stretch_scaler: Scaler
    history: int
    include_current: bool
    model: str = "window"

    @classmethod
    def from_checkpoint(cls, state: dict[str, Any]) -> "Imaginer":
        """Rebuild the networks from a checkpoint's state; refuse one whose weights do not fit them."""
        if state.get("lstm") is None:
            raise CheckpointError("the checkpoint's training stopped before the LSTM: finish it with --resume")
        t = state["config"]["train"]
        model = t.get("model", "window")
        height, width = state["image_shape"]
        latent_scaler = Scaler.from_state(state["latent_scaler"])
        ae = Autoencoder(height, width, t["latent"])
        lstm = latent_model(model, state["sensor_count"], t["lstm_hidden"], latent_scaler.kept)
        try:
            ae.load_state_dict(state["autoencoder"])
            lstm.load_state_dict(state["lstm"])
        except (RuntimeError, KeyError) as e:
            raise CheckpointError(f"the checkpoint's weights do not fit this softarm's networks: "
                                  f"{str(e).splitlines()[0][:160]}") from None
        ae.eval()
        lstm.eval()
        ae.to(memory_format=torch.channels_last)  # faster convolutions when decoding on the CPU
        return cls(ae, lstm, latent_scaler, Scaler.from_state(state["stretch_scaler"]), t["history"],
                   t["include_current"], model)

    @property
    def lead(self) -> int:
        """Frames between the last sample read and the frame imagined from it."""
        return 0 if self.include_current else 1

    def windows(self, stretch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every window of a stretch series (T, P) and the frame index each one predicts: the frames any
        model imagines, and what the ridge baseline reads."""
        windows, targets = stretch_windows(stretch, self.history, self.include_current)
        if len(targets) == 0:
            raise RecordingError(f"{len(stretch)} stretch samples are too few for a history of {self.history}")
        return windows, targets

    def predict(self, stretch: np.ndarray) -> Prediction:
        """The latent answer for every frame of a stretch series (T, P) that the model imagines."""
        return self.predict_many([stretch])[0]

    @torch.inference_mode()
    def predict_many(self, series: Sequence[np.ndarray]) -> list[Prediction]:
        """`predict` for several series at once (a stream model reads equal-length ones side by side)."""
        if self.model == "window":
            return [self.predict_windows(*self.windows(s)) for s in series]
        out: list[Optional[Prediction]] = [None] * len(series)
        for length in sorted({len(s) for s in series}):
            same = [i for i, s in enumerate(series) if len(s) == length]
            for first in range(0, len(same), STREAMS):
                group = same[first:first + STREAMS]
                for i, prediction in zip(group, self._predict_streams(np.stack([series[i] for i in group]))):
                    out[i] = prediction
        return out

    @torch.inference_mode()
    def predict_windows(self, windows: np.ndarray, targets: np.ndarray) -> Prediction:
        """The window model's answers for raw stretch windows (M, history, P) and the frames they predict."""
        x = torch.from_numpy(self.stretch_scaler.forward(windows).astype(np.float32))
        answers = [self.lstm(x[i:i + BATCH]) for i in range(0, len(x), BATCH)]
        return Prediction(targets, *(torch.cat(parts).numpy() for parts in zip(*answers)))

    @torch.inference_mode()
    def _predict_streams(self, stretch: np.ndarray) -> list[Prediction]:
        """(S, T, P) series of one length, each read from its first sample."""
        _, targets = self.windows(stretch[0])
        x = torch.from_numpy(self.stretch_scaler.forward(stretch).astype(np.float32))
        latents, log_error, _ = self.lstm(x)
        samples = targets - self.lead
        return [Prediction(targets, latents[s, samples].numpy(), log_error[s, samples].numpy())
                for s in range(len(stretch))]

    @torch.inference_mode()
    def decode(self, normalised: np.ndarray) -> np.ndarray:
        """Pixel probabilities (M, H, W) of normalised kept latents (M, K)."""
        z = torch.from_numpy(self.latent_scaler.inverse(normalised).astype(np.float32))
        return torch.cat([torch.sigmoid(self.autoencoder.decode(z[i:i + BATCH])) for i in range(0, len(z), BATCH)]).numpy()

    def imagine(self, stretch: np.ndarray) -> tuple[Prediction, np.ndarray]:
        """The prediction and the imagined pixel probabilities (M, H, W) of a whole stretch series (T, P)."""
        prediction = self.predict(stretch)
        return prediction, self.decode(prediction.latents)
