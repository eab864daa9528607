"""Adaptation: learning the new body after a lasting change, from a few seconds of camera.

What changes when an arm carries a load or a segment is damaged is how its feeling maps to its shape, and, for a
damaged segment, how the body moves: the same stretch and command now mean another pose, reached another way. So
each latent model (each member, for an ensemble) is fine-tuned whole on the window's frames, recurrent layer and
latent head together (the error head and the node head stay): `STEPS` Adam steps on the mean squared error of the
normalised latent code, reading the recording from its first sample as replay does, with an L2 pull toward the
trained weights so that a few seconds of one motion do not erase the body it knew. A refit of the latent head
alone (a ridge toward the trained head) recovered 71 % of a load's loss but 13 % of a damage's with 5 s of
camera: the recurrent layer has to learn a softened segment. The surprise's forward model and memory check are
then refitted in closed form, ridge regressions toward their weights on the same samples, so the alarm quietens
once the new body is learned. The autoencoder and the scalers stay as they were.
"""

import copy
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np
import torch

from softarm.imagine.imaginer import Imaginer
from softarm.interrupt import Stopped
from softarm.model.autoencoder import encode_frames
from softarm.model.device import tensor_on
from softarm.model.latent import LatentModel
from softarm.trust.surprise import LAGS, SurpriseModel

STEPS = 150           # Adam steps of the fine-tuning
LEARNING_RATE = 1e-3
PULL = 1e-3           # the L2 pull: PULL * the sum of squared changes of the tuned weights, beside the latent MSE
SHRINK = 0.03         # the surprise's refits' pull, relative to the mean squared feature times the samples
FROZEN = ("error", "nodes")  # parameter names' starts that fine-tuning leaves alone


@dataclass(frozen=True)
class Window:
    """The seconds the camera is on: frames [start, end) of a recording, the model's normalised inputs (T, F)
    and the frames (T, H, W)."""
    start: int
    end: int
    inputs: np.ndarray
    frames: np.ndarray


def adapt_models(imaginer: Imaginer, window: Window, stop: Callable[[], bool] = lambda: False) -> Imaginer:
    """A new imaginer whose latent models (and surprise model) fit the window's frames; the given one is unchanged.
    `stop()` is asked between fine-tuning steps: True raises Stopped."""
    lead = imaginer.latent.lead
    frames = np.arange(max(window.start, imaginer.latent.first_frame), window.end)
    codes = imaginer.latent_scaler.forward(encode_frames(imaginer.autoencoder, window.frames[frames]))
    read = window.inputs[:window.end].astype(np.float32)
    device = imaginer.latent.device  # the fine-tuning runs where the networks are
    models = [fine_tuned(model, tensor_on(read, device), tensor_on(frames - lead, device),
                         tensor_on(codes.astype(np.float32), device), stop)
              for model in (imaginer.latent, *imaginer.members)]
    surprise = imaginer.surprise
    if surprise is not None:
        surprise = adapted_surprise(surprise, models[0].states(read), read.astype(np.float64), window.start, SHRINK)
    return replace(imaginer, latent=models[0], members=tuple(models[1:]), surprise=surprise)


def fine_tuned(model: LatentModel, series: torch.Tensor, samples: torch.Tensor, codes: torch.Tensor,
               stop: Callable[[], bool] = lambda: False) -> LatentModel:
    """A copy of `model` after STEPS Adam steps on |latents_at(series, samples) - codes|^2 (mean) + PULL * |w - w0|^2
    over its parameters but the FROZEN ones."""
    tuned = copy.deepcopy(model)
    weights = {name: p for name, p in tuned.named_parameters() if not name.startswith(FROZEN)}
    start = {name: p.detach().clone() for name, p in weights.items()}
    optimiser = torch.optim.Adam(weights.values(), lr=LEARNING_RATE)
    tuned.train()
    for _ in range(STEPS):
        if stop():
            raise Stopped()
        loss = ((tuned.latents_at(series, samples) - codes) ** 2).mean()
        loss = loss + PULL * sum(((p - start[name]) ** 2).sum() for name, p in weights.items())
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
    return tuned.eval()


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
    (the latent model's states (T, H) after each normalised input sample (T, F)); their spreads and the forward
    model's correction stay (the ridge takes the change)."""
    x = model.features(inputs)[max(start - LAGS, 0):]
    y = inputs[LAGS:][max(start - LAGS, 0):, list(model.felt)] - model.corrected(x)
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
