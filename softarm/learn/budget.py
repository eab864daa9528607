"""`--minutes`: fit both networks' schedules into a wall-clock budget, from the step times measured here.

A few forward and backward passes of each network on a batch of the real shapes (no optimiser step,
so the run itself is unchanged) give the seconds per step; both schedules then shrink by one factor
so that their steps, the encoding of every frame and the scoring fit what is left of the budget. The
result is written into the config as `train.max_steps_*`, so the checkpoint records it and `--resume`
continues the same schedule. Step times differ between machines: a budgeted run is not reproducible
elsewhere, an unbudgeted one is.
"""

import copy
import math
import time
from typing import Callable

import torch
import torch.nn.functional as F

from softarm.config import override
from softarm.learn.precision import forward_precision
from softarm.learn.train import schedules
from softarm.learn.train_state import TrainState
from softarm.model.registry import latent_model_class

PROBE_STEPS = 3
RESERVE = 0.1  # of the budget, kept for encoding the frames and scoring held-out data


def fit_to_minutes(state: TrainState, minutes: float, spent: float) -> None:
    """Cap the schedules of `state` (not yet started) so that training ends within `minutes`, `spent`
    seconds of which are gone already (loading the data)."""
    ae, latent = schedules(state)
    ae_step, latent_step = _autoencoder_step(state), _latent_step(state)
    budget = minutes * 60 * (1 - RESERVE) - spent
    scale = min(1.0, max(budget, 0.0) / (ae.total * ae_step + latent.total * latent_step))
    state.config = override(state.config, {"train.max_steps_ae": max(1, math.floor(ae.total * scale)),
                                           "train.max_steps_lstm": max(1, math.floor(latent.total * scale))})


def _seconds_per_step(model: torch.nn.Module, loss: Callable[[], torch.Tensor], precision: str) -> float:
    """Seconds of one forward and backward pass, the forward in the training's precision; the model's weights
    and statistics are left as they were."""
    saved = copy.deepcopy(model.state_dict())  # batch normalisation updates its running statistics in training mode
    model.train()

    def step() -> None:
        with forward_precision(precision):
            value = loss()
        value.backward()

    step()  # warm up
    start = time.perf_counter()
    for _ in range(PROBE_STEPS):
        step()
    seconds = (time.perf_counter() - start) / PROBE_STEPS
    model.zero_grad(set_to_none=True)
    model.load_state_dict(saved)
    return seconds


def _autoencoder_step(state: TrainState) -> float:
    frames = torch.from_numpy(state.data.frames("train")[:state.config.train.batch_ae]).float()
    loss = lambda: F.binary_cross_entropy_with_logits(state.autoencoder(frames), frames)  # noqa: E731
    return _seconds_per_step(state.autoencoder, loss, state.config.train.precision)


def _latent_step(state: TrainState) -> float:
    """A stand-in of the latent model's size, on a dummy batch of its real training shape."""
    t, features = state.config.train, sum(state.data.widths)
    model = latent_model_class(t.model)
    network = model(features, t.latent, t)
    batch = model.dummy_batch(t, features)
    return _seconds_per_step(network, lambda: network(batch)[0].float().square().mean(), t.precision)
