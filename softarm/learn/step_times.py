"""Seconds per optimisation step of each network, measured here on batches of the real shapes: what `--minutes`
sizes the schedules by, and what `train.precision = "auto"` chooses the arithmetic by.

A few forward and backward passes (no optimiser step, the weights and batch statistics restored after), so the
run itself is unchanged by being measured.
"""

import copy
import statistics
import time
from typing import Callable, Sequence

import torch
import torch.nn.functional as F

from softarm.learn.precision import forward_precision, has_bf16
from softarm.learn.train_state import TrainState
from softarm.model.device import device_of, synchronize, tensor_on
from softarm.registry import latent_model_class

ROUNDS = 5  # timed steps of each precision, taken in turns
BF16_MARGIN = 1.05  # how much faster bf16 must run each network's step to be chosen


def seconds_per_step(model: torch.nn.Module, loss: Callable[[], torch.Tensor],
                     precisions: Sequence[str]) -> dict[str, float]:
    """Median seconds of one forward and backward pass in each precision, the precisions taking turns (a shared
    machine's drift falls on all alike); the model's weights and statistics are left as they were."""
    saved = copy.deepcopy(model.state_dict())  # batch normalisation updates its running statistics in training mode
    model.train()
    device = device_of(model)

    def step(precision: str) -> float:
        synchronize(device)  # a GPU's queue empty before the clock starts, and again before it stops
        start = time.perf_counter()
        with forward_precision(precision, device.type):
            value = loss()
        value.backward()
        synchronize(device)
        return time.perf_counter() - start

    for precision in precisions:
        step(precision)  # warm up
    times = [[step(precision) for precision in precisions] for _ in range(ROUNDS)]
    model.zero_grad(set_to_none=True)
    model.load_state_dict(saved)
    return {precision: statistics.median(column) for precision, column in zip(precisions, zip(*times))}


def autoencoder_steps(state: TrainState, precisions: Sequence[str]) -> dict[str, float]:
    frames = tensor_on(state.data.frames("train")[:state.config.train.batch_ae], state.device).float()
    loss = lambda: F.binary_cross_entropy_with_logits(state.autoencoder(frames), frames)  # noqa: E731
    return seconds_per_step(state.autoencoder, loss, precisions)


def latent_steps(state: TrainState, precisions: Sequence[str]) -> dict[str, float]:
    """A stand-in of the latent model's size, on a dummy batch of its real training shape."""
    t, features = state.config.train, sum(state.data.widths)
    model = latent_model_class(t.model)
    network = model(features, t.latent, t).to(state.device)
    batch = model.dummy_batch(t, features).to(state.device)
    return seconds_per_step(network, lambda: network(batch)[0].float().square().mean(), precisions)


def fastest_precision(state: TrainState) -> str:
    """"bf16" where autocast makes both networks' steps at least BF16_MARGIN faster on this machine, measured;
    "fp32" otherwise. Whether bf16 pays depends on the chip, not on its flags (bench/training.py: 1.2x for both on
    an AMD EPYC with AVX-512 BF16; on an Intel Xeon with the same flags and no AMX 1.0x for the autoencoder, whose
    probe then wavers by ±6 %, and 0.7x for the stream LSTM). Asking it of each network keeps a wavering
    autoencoder from trading the LSTM's clear loss for nothing, and the margin keeps fp32's exact arithmetic where
    bf16 gains no more than noise; without native bf16 nothing is tried."""
    if not has_bf16(state.device):
        return "fp32"
    both = ("fp32", "bf16")
    steps = (autoencoder_steps(state, both), latent_steps(state, both))
    return "bf16" if all(step["bf16"] * BF16_MARGIN < step["fp32"] for step in steps) else "fp32"
