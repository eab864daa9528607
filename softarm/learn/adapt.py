"""Adaptation: learning the new body after a lasting change, from a few seconds of camera.

What changes when an arm carries a load or a segment is damaged is how its felt state maps to its shape: the
recurrent layer still reads the stretch and the command and keeps the memory of the motion, but the same
feeling now means another pose. So only the latent model's last layer (the linear head from the recurrent state
to the latent code; each member's, for an ensemble) is fitted again, in closed form: ridge regression from the
states of the camera's frames to their codes, shrunk toward the trained head so that a few seconds of one
motion do not erase the body it knew. The surprise's forward model is refitted the same way on the same
samples (the stretch is always felt), so the alarm quietens once the new body is learned. The recurrent layer,
the error head, the autoencoder and the scalers stay as they were.
"""

from dataclasses import dataclass, replace

import numpy as np
import torch

from softarm.model.autoencoder import encode_frames
from softarm.model.imaginer import Imaginer
from softarm.model.latent import LatentModel
from softarm.model.surprise import LAGS, SurpriseModel

SHRINK = 0.03   # the pull toward the trained weights, relative to the mean squared feature times the samples


@dataclass(frozen=True)
class Window:
    """The seconds the camera is on: frames [start, end) of a recording, the model's normalised inputs (T, F)
    and the frames (T, H, W)."""
    start: int
    end: int
    inputs: np.ndarray
    frames: np.ndarray


def adapt_heads(imaginer: Imaginer, window: Window, shrink: float = SHRINK) -> Imaginer:
    """A new imaginer whose latent heads (and surprise model) fit the window's frames; the given one is unchanged."""
    lead = imaginer.latent.lead
    frames = np.arange(max(window.start, imaginer.latent.first_frame), window.end)
    codes = imaginer.latent_scaler.forward(encode_frames(imaginer.autoencoder, window.frames[frames]))
    read = window.inputs[:window.end].astype(np.float32)
    states = [model.states(read) for model in (imaginer.latent, *imaginer.members)]
    models = [with_head(model, *ridge_toward(s[frames - lead], codes, *head_of(model), shrink))
              for model, s in zip((imaginer.latent, *imaginer.members), states)]
    surprise = imaginer.surprise
    if surprise is not None:
        surprise = adapted_surprise(surprise, states[0], read.astype(np.float64), window.start, shrink)
    return Imaginer(imaginer.autoencoder, models[0], imaginer.latent_scaler, imaginer.inputs, tuple(models[1:]),
                    surprise, imaginer.trust)


def head_of(model: LatentModel) -> tuple[np.ndarray, np.ndarray]:
    """The latent head as (weights (H, K), bias (K,)), float64."""
    return model.head.weight.detach().double().numpy().T, model.head.bias.detach().double().numpy()


def with_head(model: LatentModel, weights: np.ndarray, bias: np.ndarray) -> LatentModel:
    """A copy of `model` with another latent head."""
    copy = type(model)(model.rnn.input_size, model.head.out_features, model.settings,
                       model.nodes.out_features if model.nodes is not None else 0)
    copy.load_state_dict(model.state_dict())
    with torch.no_grad():
        copy.head.weight.copy_(torch.from_numpy(weights.T))
        copy.head.bias.copy_(torch.from_numpy(bias))
    return copy.eval()


def ridge_toward(x: np.ndarray, y: np.ndarray, weights: np.ndarray, bias: np.ndarray,
                 shrink: float) -> tuple[np.ndarray, np.ndarray]:
    """argmin |y - x W - b|^2 + shrink * mean(x^2) * N * (|W - W0|^2 + |b - b0|^2): a ridge on the change."""
    xa = np.concatenate([x, np.ones((len(x), 1))], axis=1)
    start = np.concatenate([weights, bias[None]])
    residual = y - xa @ start
    penalty = shrink * float(np.mean(xa ** 2)) * len(x) * np.eye(xa.shape[1])
    change = np.linalg.solve(xa.T @ xa + penalty, xa.T @ residual)
    new = start + change
    return new[:-1], new[-1]


def adapted_surprise(model: SurpriseModel, states: np.ndarray, inputs: np.ndarray, start: int,
                     shrink: float) -> SurpriseModel:
    """The forward model and the memory check refitted toward their weights on the samples from `start` on
    (the latent model's states (T, H) after each normalised input sample (T, F)); their spreads stay."""
    x = model.features(inputs)[max(start - LAGS, 0):]
    y = inputs[LAGS:][max(start - LAGS, 0):, list(model.felt)]
    model = replace(model, weights=toward(x, y, model.weights, shrink))
    if model.memory is None:
        return model
    keep = np.arange(max(start, 1), len(inputs))
    keep = keep[np.isfinite(states[keep - 1]).all(axis=1)]
    memory = model.memory
    x = memory.features(states[keep - 1], inputs[keep])
    return replace(model, memory=replace(memory, weights=toward(x, inputs[keep][:, list(model.felt)], memory.weights,
                                                                 shrink)))


def toward(x: np.ndarray, y: np.ndarray, weights: np.ndarray, shrink: float) -> np.ndarray:
    """`ridge_toward` for a map whose features (and weights' rows) end with the constant."""
    new, bias = ridge_toward(x[:, :-1], y, weights[:-1], weights[-1], shrink)
    return np.concatenate([new, bias[None]])
