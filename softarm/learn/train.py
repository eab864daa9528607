"""The training loop: the autoencoder on frames, then the LSTM from stretch windows to latents.

The loop is written out below, top to bottom: shuffle with a generator seeded by (seed, phase,
epoch), step through batches on a cosine learning rate, score held-out frames, save a checkpoint
after every epoch. Because every epoch's randomness comes from its own seed and the learning rate
from the step count, a run resumed from any epoch's checkpoint ends exactly where an uninterrupted
run ends (on the CPU).
"""

import math
from pathlib import Path
from typing import Callable, Optional

import numpy as np
import torch
import torch.nn.functional as F

from softarm.learn.codes import LatentCodes
from softarm.learn.evaluate import imaginer_of, reconstruct
from softarm.learn.observer import NoObserver, Progress, TrainingObserver
from softarm.learn.scaler import Scaler
from softarm.learn.train_state import TrainState

CLIP_FRAMES = 100  # the held-out clip shown each epoch: the first second of the imagination segment



def fit(state: TrainState, out: Path, observer: TrainingObserver, progress: Progress, stop: Callable[[], bool]) -> bool:
    """Both phases from wherever `state` stands; False when `stop()` interrupted it."""
    t, data = state.config.train, state.data
    if state.phase == "ae":
        frames = torch.from_numpy(data.frames("train"))  # uint8: a batch becomes float only when used
        test = data.frames("test")

        def ae_loss(index: torch.Tensor) -> torch.Tensor:
            x = frames[index].float()
            return F.binary_cross_entropy_with_logits(state.autoencoder(x), x)

        while state.epoch < t.epochs_ae:
            loss = run_epoch(state, state.autoencoder, state.ae_optimizer, len(frames), t.batch_ae, t.epochs_ae,
                             t.lr_ae, ae_loss, stop)
            if loss is None:
                return False
            end_epoch(state, out, observer, progress, loss, ae_test_loss(state, test))
            show_clip(state, observer, imagination=False)
        state.phase, state.epoch = "lstm", 0
        state.make_lstm(*fit_scalers(state, state.codes()))
        state.save(out)
    if state.phase == "lstm":
        x, y = lstm_pairs(state, state.codes(), "train")
        x_val, y_val = lstm_pairs(state, state.codes(), "test")
        while state.epoch < t.epochs_lstm:
            loss = run_epoch(state, state.lstm, state.lstm_optimizer, len(x), t.batch_lstm, t.epochs_lstm, t.lr_lstm,
                             lambda index: F.mse_loss(state.lstm(x[index]), y[index]), stop)
            if loss is None:
                return False
            state.lstm.eval()
            with torch.no_grad():
                val = F.mse_loss(state.lstm(x_val), y_val).item()
            end_epoch(state, out, observer, progress, loss, val)
            if state.epoch % 10 == 0 or state.epoch == t.epochs_lstm:
                show_clip(state, observer, imagination=True)
        state.phase = "done"
    return True


def run_epoch(state: TrainState, model: torch.nn.Module, optimizer: torch.optim.Optimizer, items: int, batch: int,
              epochs: int, base_lr: float, batch_loss: Callable[[torch.Tensor], torch.Tensor],
              stop: Callable[[], bool]) -> Optional[float]:
    """One epoch of either network: its mean training loss, or None when `stop()` interrupted it."""
    steps_per_epoch = math.ceil(items / batch)
    model.train()
    order, total = epoch_order(items, state.config.train.seed, 0 if state.phase == "ae" else 1, state.epoch), 0.0
    for i, first in enumerate(range(0, items, batch)):
        for group in optimizer.param_groups:
            group["lr"] = cosine_lr(base_lr, state.epoch * steps_per_epoch + i, epochs * steps_per_epoch)
        index = order[first:first + batch]
        loss = batch_loss(index)
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()
        total += loss.item() * len(index)
        if stop():
            return None
    return total / items


def end_epoch(state: TrainState, out: Path, observer: TrainingObserver, progress: Progress, train_loss: float,
              held_out: float) -> None:
    """Count the epoch, keep its losses, save the checkpoint, report to the view and the progress bar."""
    lstm = state.phase != "ae"
    names = ("lstm_train", "lstm_val") if lstm else ("ae_train", "ae_test")
    state.epoch += 1
    for name, value in zip(names, (train_loss, held_out)):
        state.losses[name].append(value)
        observer.loss(name, training_step(state), value)
    state.save(out)
    t = state.config.train
    progress("lstm" if lstm else "ae", state.epoch, t.epochs_lstm if lstm else t.epochs_ae,
             dict(zip(names, (train_loss, held_out))))


def training_step(state: TrainState) -> int:
    """Optimisation steps taken so far over both networks: one axis for every loss curve of the live view."""
    t, data = state.config.train, state.data
    ae_steps = math.ceil(data.count("train") / t.batch_ae)
    lstm_steps = math.ceil(data.count("train", t.history, t.include_current) / t.batch_lstm)
    return len(state.losses["ae_train"]) * ae_steps + len(state.losses["lstm_train"]) * lstm_steps


@torch.no_grad()
def ae_test_loss(state: TrainState, frames: np.ndarray) -> float:
    """Mean per-pixel BCE of the autoencoder on held-out frames."""
    state.autoencoder.eval()
    total = 0.0
    for i in range(0, len(frames), 512):
        x = torch.from_numpy(frames[i:i + 512]).float()
        total += F.binary_cross_entropy_with_logits(state.autoencoder(x), x, reduction="sum").item()
    return total / frames.size


def fit_scalers(state: TrainState, codes: LatentCodes) -> tuple[Scaler, Scaler]:
    """Drop latent features constant over the training frames; normalise latents and stretch with training statistics."""
    data = state.data
    latent = Scaler.fit(codes.segment(data, "train"), state.config.train.min_feature_std)
    stretch = Scaler.fit(np.concatenate([s.stretch[slice(*s.segment("train"))] for s in data.sequences]))
    return latent, stretch


def lstm_pairs(state: TrainState, codes: LatentCodes, segment: str) -> tuple[torch.Tensor, torch.Tensor]:
    """Normalised stretch windows of a segment and the normalised latent code each one predicts."""
    t = state.config.train
    windows, targets = state.data.windows(segment, t.history, t.include_current)
    latents = state.latent_scaler.forward(codes.of(targets))
    x = state.stretch_scaler.forward(windows).astype(np.float32)
    return torch.from_numpy(x), torch.from_numpy(latents.astype(np.float32))


def show_clip(state: TrainState, observer: TrainingObserver, imagination: bool) -> None:
    """The first second of the imagination segment: truth | reconstruction | imagination (once the LSTM learns)."""
    if isinstance(observer, NoObserver):
        return
    seq = state.data.sequences[0]
    start, end = seq.segment("imagine")
    frames = seq.frames[start:min(end, start + CLIP_FRAMES)]
    recon = reconstruct(state, frames)
    imagined = None
    if imagination:
        targets, probs = imaginer_of(state).imagine(seq.stretch[start:start + len(frames)])
        imagined = np.zeros_like(recon)
        imagined[targets] = probs
    observer.clip(training_step(state), seq.times[start:start + len(frames)], frames, recon, imagined)


def cosine_lr(base: float, step: int, total: int) -> float:
    """Cosine decay from base to base/100 over the run: a function of the step alone, so resume is exact."""
    return base * (0.01 + 0.99 * 0.5 * (1 + math.cos(math.pi * min(step, total) / max(total, 1))))


def epoch_order(n: int, seed: int, phase: int, epoch: int) -> torch.Tensor:
    """The shuffle of one epoch, from its own seed: a resumed run shuffles exactly as an uninterrupted one."""
    return torch.randperm(n, generator=torch.Generator().manual_seed(seed * 1_000_003 + phase * 10_007 + epoch))
