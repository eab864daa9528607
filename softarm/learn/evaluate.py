"""Held-out scores of a finished training: the autoencoder on the test segment, imagination on the last
segment, and beside it the ridge and mean-frame baselines and the AE ceiling (decode the true latent), all
on the same frames and scored by the model room's one scorer, so every number has its yardstick."""

from typing import Any, Optional

import numpy as np

from softarm.imagine.answers import score_answers
from softarm.imagine.imaginer import Imaginer
from softarm.learn.codes import LatentCodes
from softarm.learn.dataset import Dataset
from softarm.learn.train_state import TrainState
from softarm.model import node_ridge
from softarm.model.autoencoder import reconstruct
from softarm.model.baselines import Baselines, ridge_fit
from softarm.model.latent import LatentModel
from softarm.model.metrics import image_scores, summarise
from softarm.model.prediction import Prediction
from softarm.registry import trust_class
from softarm.trust.confidence import ErrorHeadTrust

MAX_SCORED = 10_000  # held-out frames scored per segment: a corpus's metrics cost what one long recording's do


def evenly(count: int, most: int) -> np.ndarray:
    """Indices of at most `most` of `count` items, evenly spaced (all of them when there are few)."""
    return np.arange(count) if count <= most else np.linspace(0, count - 1, most).round().astype(int)


def imaginer_of(state: TrainState, latent: Optional[LatentModel] = None) -> Imaginer:
    """The state's networks in eval mode, as replay would use them (with `latent`: that latent model alone, an
    ensemble member's validation)."""
    state.autoencoder.eval()
    if latent is not None:
        return Imaginer(state.autoencoder, latent.eval(), state.latent_scaler, state.inputs)
    if state.latent is not None:
        state.latent.eval()
    members = tuple(m.eval() for m in state.member_networks()) if state.phase == "done" else ()
    return Imaginer(state.autoencoder, state.latent, state.latent_scaler, state.inputs, members, state.surprise,
                    trust_class(state.config.train.confidence).build(state.calibration)
                    or ErrorHeadTrust(),  # the calibrated way, before its map is fitted
                    state.baselines.ridge if state.baselines is not None else None)


def segment_prediction(imaginer: Imaginer, data: Dataset, segment: str) -> Prediction:
    """The answers for every frame of a segment, all recordings in order, that a window inside the segment
    reaches (the frames `Dataset.windows` lists): targets are (recording, frame) pairs (M, 2)."""
    return imaginer.predict_segments([s.inputs for s in data.sequences], [s.segment(segment) for s in data.sequences])


def held_out_mse(imaginer: Imaginer, data: Dataset, codes: LatentCodes) -> float:
    """Mean squared error of the normalised latent over the test segment (the held-out recordings whole)."""
    prediction = segment_prediction(imaginer, data, "test")
    seen = data.seen(prediction.targets)
    errors = prediction.latents[seen] - imaginer.latent_scaler.forward(codes.of(prediction.targets)[seen])
    return float(np.mean(errors ** 2))


def fit_baselines(state: TrainState) -> Baselines:
    """The mean training frame, a ridge map from the same windows to the same latents as the latent model's, and
    the privileged ridge from 2 s of inputs to the node positions (node_ridge.py)."""
    t, data = state.config.train, state.data
    windows, targets = data.windows("train", t.history, t.lead)
    seen = data.seen(targets)  # a camera's gap is no target
    windows, targets = windows[seen], targets[seen]
    ridge = ridge_fit(state.inputs.normalise(windows), state.latent_scaler.forward(state.codes().of(targets)))
    nodes = node_ridge.fit([(state.inputs.normalise(s.inputs), s.positions, s.segment("train")[1])
                            for s in data.sequences if s.positions is not None], t.lead)
    return Baselines(mean_frame=data.frames("train").mean(), ridge=ridge, nodes=nodes)


def training_metrics(state: TrainState) -> dict[str, Any]:
    """The metrics document written beside the checkpoint (README: Results), once its baselines are fitted."""
    t, data, baselines = state.config.train, state.data, state.baselines
    imaginer = imaginer_of(state)
    test_frames = data.frames("test")
    test_frames = test_frames[evenly(len(test_frames), MAX_SCORED)]
    imagination, imagine_mse = scored_answers(state, baselines, imaginer, "imagine")
    metrics = {
        "autoencoder_test": image_scores(reconstruct(state.autoencoder, test_frames), test_frames,
                                         data.pixels_per_metre),
        "latent_mse": {"test": held_out_mse(imaginer, data, state.codes()), "imagine": imagine_mse},
        "imagination": imagination,
        "counts": {"train_frames": data.count("train"), "test_frames": int(len(test_frames)),
                   "imagination_predictions": min(data.window_count("imagine", t.history, t.lead), MAX_SCORED),
                   "kept_latent_features": state.latent_scaler.kept, "latent_features": int(t.latent)},
        "recordings": data.fingerprints(),
        "inputs": list(t.inputs),  # the channels read: chosen by the data where `train.inputs` named none
    }
    held_out = [n for n, seq in enumerate(data.sequences) if seq.held_out]
    if held_out:
        metrics["validation"] = {"recordings": [data.sequences[n].name for n in held_out],
                                 **scored_answers(state, baselines, imaginer, "test", held_out)[0]}
    return metrics


def scored_answers(state: TrainState, baselines: Baselines, imaginer: Imaginer, segment: str,
                   recordings: Optional[list[int]] = None) -> tuple[dict[str, Any], float]:
    """Mean scores of the four answers on (at most MAX_SCORED of) the frames of a segment, of some recordings
    or all; and the model's latent MSE there."""
    t, data = state.config.train, state.data
    windows, targets = data.windows(segment, t.history, t.lead)
    prediction = segment_prediction(imaginer, data, segment)
    chosen = np.isin(targets[:, 0], recordings) if recordings is not None else np.ones(len(targets), bool)
    chosen &= data.seen(targets)  # the camera's gaps are not scored
    keep = np.flatnonzero(chosen)[evenly(int(chosen.sum()), MAX_SCORED)]
    windows, targets, predicted = windows[keep], targets[keep], prediction.latents[keep]
    true_latent = imaginer.latent_scaler.forward(state.codes().of(targets))
    scores = score_answers(imaginer, baselines, data.target_frames(targets), imaginer.decode(predicted),
                           state.inputs.normalise(windows), true_latent, data.pixels_per_metre)
    return ({name: summarise(per_frame) for name, per_frame in scores.items()},
            float(np.mean((predicted - true_latent) ** 2)))
