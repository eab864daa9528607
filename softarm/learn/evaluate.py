"""Held-out scores of a finished training: the autoencoder on the test segment, imagination on the
last segment, and beside it the ridge and mean-frame baselines and the AE ceiling (decode the true
latent), all on the same frames, so every number has its yardstick."""

from typing import Any

import numpy as np
import torch

from softarm.learn.imaginer import Imaginer
from softarm.learn.baselines import Baselines, ridge_fit, ridge_predict
from softarm.learn.metrics import image_scores
from softarm.learn.train_state import TrainState

AE_BATCH = 512
MAX_SCORED = 10_000  # held-out frames scored per segment: a corpus's metrics cost what one long recording's do


def evenly(count: int, most: int) -> np.ndarray:
    """Indices of at most `most` of `count` items, evenly spaced (all of them when there are few)."""
    return np.arange(count) if count <= most else np.linspace(0, count - 1, most).round().astype(int)


def imaginer_of(state: TrainState) -> Imaginer:
    """The state's networks in eval mode, as replay would use them."""
    state.autoencoder.eval()
    if state.lstm is not None:
        state.lstm.eval()
    t = state.config.train
    return Imaginer(state.autoencoder, state.lstm, state.latent_scaler, state.stretch_scaler, t.history,
                    t.include_current)


@torch.no_grad()
def reconstruct(state: TrainState, frames: np.ndarray) -> np.ndarray:
    """Autoencoder pixel probabilities (M, H, W) of frames (M, H, W)."""
    state.autoencoder.eval()
    chunks = np.array_split(frames, max(1, len(frames) // AE_BATCH))
    return torch.cat([torch.sigmoid(state.autoencoder(torch.from_numpy(c).float())) for c in chunks]).numpy()


def fit_baselines(state: TrainState) -> Baselines:
    """The mean training frame and a ridge map from the same windows to the same latents as the LSTM's."""
    t, data = state.config.train, state.data
    windows, targets = data.windows("train", t.history, t.include_current)
    ridge = ridge_fit(state.stretch_scaler.forward(windows), state.latent_scaler.forward(state.codes().of(targets)))
    return Baselines(mean_frame=data.frames("train").mean(axis=0), ridge=ridge)


def evaluate(state: TrainState, baselines: Baselines) -> dict[str, Any]:
    """The metrics document written beside the checkpoint (README: Results)."""
    codes = state.codes()
    t, data, scale = state.config.train, state.data, state.latent_scaler
    ppm = state.config.camera.pixels_per_metre
    imaginer = imaginer_of(state)
    test_frames = data.frames("test")
    test_frames = test_frames[evenly(len(test_frames), MAX_SCORED)]
    windows, targets = data.windows("imagine", t.history, t.include_current)
    keep = evenly(len(targets), MAX_SCORED)
    windows, targets = windows[keep], targets[keep]
    truth = data.target_frames(targets)
    true_latent = scale.forward(codes.of(targets))
    predicted = imaginer.latents(windows)
    ridge_latent = ridge_predict(baselines.ridge, state.stretch_scaler.forward(windows))
    val_windows, val_targets = data.windows("test", t.history, t.include_current)
    val_latent = scale.forward(codes.of(val_targets))
    return {
        "autoencoder_test": image_scores(reconstruct(state, test_frames), test_frames, ppm),
        "lstm_latent_mse": {
            "test": float(np.mean((imaginer.latents(val_windows) - val_latent) ** 2)),
            "imagine": float(np.mean((predicted - true_latent) ** 2))},
        "imagination": {
            "lstm": image_scores(imaginer.decode(predicted), truth, ppm),
            "ridge": image_scores(imaginer.decode(ridge_latent), truth, ppm),
            "mean_frame": image_scores(np.broadcast_to(baselines.mean_frame, truth.shape), truth, ppm),
            "ae_ceiling": image_scores(imaginer.decode(true_latent), truth, ppm)},
        "counts": {"train_frames": data.count("train"), "test_frames": int(len(test_frames)),
                   "imagination_predictions": int(len(targets)), "kept_latent_features": scale.kept,
                   "latent_features": int(t.latent)},
        "recordings": data.fingerprints(),
    }
