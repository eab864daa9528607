"""Held-out scores of a finished training: the autoencoder on the test segment, imagination on the
last segment, and beside it the ridge and mean-frame baselines and the AE ceiling (decode the true
latent), all on the same frames, so every number has its yardstick."""

from typing import Any, Optional

import numpy as np
import torch

from softarm.learn.codes import LatentCodes
from softarm.learn.dataset import Dataset
from softarm.learn.imaginer import Imaginer, Prediction
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
                    t.include_current, t.model)


def segment_prediction(imaginer: Imaginer, data: Dataset, segment: str) -> Prediction:
    """The answers for every frame of a segment, all recordings in order, that a window inside the segment
    reaches (the frames `Dataset.windows` lists): targets are (recording, frame) pairs (M, 2). The stream
    model reads each recording from its start, as it would online; the window model reads only the
    segment's windows."""
    if imaginer.model == "window":
        return imaginer.predict_windows(*data.windows(segment, imaginer.history, imaginer.include_current))
    skip = imaginer.history - 1 + imaginer.lead
    parts = []
    for n, (seq, p) in enumerate(zip(data.sequences, imaginer.predict_many([s.stretch for s in data.sequences]))):
        start, end = seq.segment(segment)
        p = p.take((p.targets >= start + skip) & (p.targets < end))
        parts.append(Prediction(np.stack([np.full(len(p.targets), n), p.targets], axis=1), p.latents, p.log_error))
    return Prediction(*(np.concatenate(arrays) for arrays in zip(*((p.targets, p.latents, p.log_error) for p in parts))))


def held_out_mse(imaginer: Imaginer, data: Dataset, codes: LatentCodes) -> float:
    """Mean squared error of the normalised latent over the test segment (the held-out recordings whole)."""
    prediction = segment_prediction(imaginer, data, "test")
    return float(np.mean((prediction.latents - imaginer.latent_scaler.forward(codes.of(prediction.targets))) ** 2))


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
    t, data, scale = state.config.train, state.data, state.latent_scaler
    imaginer = imaginer_of(state)
    test_frames = data.frames("test")
    test_frames = test_frames[evenly(len(test_frames), MAX_SCORED)]
    imagination, imagine_mse = scored_answers(state, baselines, imaginer, "imagine")
    metrics = {
        "autoencoder_test": image_scores(reconstruct(state, test_frames), test_frames, state.config.camera.pixels_per_metre),
        "lstm_latent_mse": {"test": held_out_mse(imaginer, data, state.codes()), "imagine": imagine_mse},
        "imagination": imagination,
        "counts": {"train_frames": data.count("train"), "test_frames": int(len(test_frames)),
                   "imagination_predictions": min(data.count("imagine", t.history, t.include_current), MAX_SCORED),
                   "kept_latent_features": scale.kept, "latent_features": int(t.latent)},
        "recordings": data.fingerprints(),
    }
    held_out = [n for n, seq in enumerate(data.sequences) if seq.held_out]
    if held_out:
        metrics["validation"] = {"recordings": [data.sequences[n].name for n in held_out],
                                 **scored_answers(state, baselines, imaginer, "test", held_out)[0]}
    return metrics


def scored_answers(state: TrainState, baselines: Baselines, imaginer: Imaginer, segment: str,
                   recordings: Optional[list[int]] = None) -> tuple[dict[str, Any], float]:
    """Image scores of the model, the ridge map, the mean frame and the AE ceiling on (at most MAX_SCORED of)
    the frames of a segment, of some recordings or all; and the model's latent MSE there."""
    t, data, scale = state.config.train, state.data, state.latent_scaler
    windows, targets = data.windows(segment, t.history, t.include_current)
    prediction = segment_prediction(imaginer, data, segment)
    chosen = np.isin(targets[:, 0], recordings) if recordings is not None else np.ones(len(targets), bool)
    keep = np.flatnonzero(chosen)[evenly(int(chosen.sum()), MAX_SCORED)]
    windows, targets, predicted = windows[keep], targets[keep], prediction.latents[keep]
    truth = data.target_frames(targets)
    true_latent = scale.forward(state.codes().of(targets))
    ridge_latent = ridge_predict(baselines.ridge, state.stretch_scaler.forward(windows))
    ppm = state.config.camera.pixels_per_metre
    return {"lstm": image_scores(imaginer.decode(predicted), truth, ppm),
            "ridge": image_scores(imaginer.decode(ridge_latent), truth, ppm),
            "mean_frame": image_scores(np.broadcast_to(baselines.mean_frame, truth.shape), truth, ppm),
            "ae_ceiling": image_scores(imaginer.decode(true_latent), truth, ppm)}, \
        float(np.mean((predicted - true_latent) ** 2))
