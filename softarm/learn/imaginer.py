"""Imagination: stretch windows -> LSTM -> normalised latent -> decoder -> frame probabilities.

An `Imaginer` holds the trained networks and the training statistics; training uses it for its
metrics and `softarm replay` for whole recordings, so both compute imagination the same way.
"""

from dataclasses import dataclass
from typing import Any

import numpy as np
import torch

from softarm.learn.dataset import stretch_windows
from softarm.errors import CheckpointError, RecordingError
from softarm.learn.scaler import Scaler
from softarm.learn.models import Autoencoder, StretchToLatent

BATCH = 256  # fastest decoding batch on a 2-core CPU


@dataclass
class Imaginer:
    autoencoder: Autoencoder
    lstm: StretchToLatent
    latent_scaler: Scaler
    stretch_scaler: Scaler
    history: int
    include_current: bool

    @classmethod
    def from_checkpoint(cls, state: dict[str, Any]) -> "Imaginer":
        """Rebuild the networks from a checkpoint's state; refuse one whose weights do not fit them."""
        if state.get("lstm") is None:
            raise CheckpointError("the checkpoint's training stopped before the LSTM: finish it with --resume")
        t = state["config"]["train"]
        height, width = state["image_shape"]
        latent_scaler = Scaler.from_state(state["latent_scaler"])
        ae = Autoencoder(height, width, t["latent"])
        lstm = StretchToLatent(state["sensor_count"], t["lstm_hidden"], latent_scaler.kept)
        try:
            ae.load_state_dict(state["autoencoder"])
            lstm.load_state_dict(state["lstm"])
        except (RuntimeError, KeyError) as e:
            raise CheckpointError(f"the checkpoint's weights do not fit this softarm's networks: "
                                  f"{str(e).splitlines()[0][:160]}") from None
        ae.eval()
        lstm.eval()
        ae.to(memory_format=torch.channels_last)  # faster convolutions when decoding on the CPU
        return cls(ae, lstm, latent_scaler, Scaler.from_state(state["stretch_scaler"]), t["history"], t["include_current"])

    def windows(self, stretch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every window of a stretch series (T, P) and the frame index each one predicts."""
        windows, targets = stretch_windows(stretch, self.history, self.include_current)
        if len(targets) == 0:
            raise RecordingError(f"{len(stretch)} stretch samples are too few for a history of {self.history}")
        return windows, targets

    @torch.inference_mode()
    def latents(self, windows: np.ndarray) -> np.ndarray:
        """Normalised kept latents (M, K) predicted from raw stretch windows (M, history, P)."""
        x = torch.from_numpy(self.stretch_scaler.forward(windows).astype(np.float32))
        return torch.cat([self.lstm(x[i:i + BATCH]) for i in range(0, len(x), BATCH)]).numpy()

    @torch.inference_mode()
    def decode(self, normalised: np.ndarray) -> np.ndarray:
        """Pixel probabilities (M, H, W) of normalised kept latents (M, K)."""
        z = torch.from_numpy(self.latent_scaler.inverse(normalised).astype(np.float32))
        return torch.cat([torch.sigmoid(self.autoencoder.decode(z[i:i + BATCH])) for i in range(0, len(z), BATCH)]).numpy()

    def imagine(self, stretch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(frame indices, probabilities (M, H, W)) imagined from a whole stretch series (T, P)."""
        windows, targets = self.windows(stretch)
        return targets, self.decode(self.latents(windows))
