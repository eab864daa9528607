"""The training loop: the autoencoder on frames, then the LSTM from stretch windows to latents.

The loop is written out below, top to bottom: shuffle with a generator seeded by (seed, phase,
epoch), step through batches on a cosine learning rate, score held-out frames, save a checkpoint
after every epoch. Because every epoch's randomness comes from its own seed and the learning rate
from the step count, a run resumed from any epoch's checkpoint ends exactly where an uninterrupted
run ends (on the CPU).
"""

import math
from dataclasses import dataclass
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



@dataclass(frozen=True)
class Schedule:
    """One phase's optimisation steps: epochs of shuffled batches, cut at `total` steps."""
    steps_per_epoch: int
    total: int

    @property
    def epochs(self) -> int:
        return math.ceil(self.total / self.steps_per_epoch)


def schedules(state: TrainState) -> tuple[Schedule, Schedule]:
    """The autoencoder's and the LSTM's: `epochs_*` epochs, at most `max_steps_*` steps (0: no cap), so that
    a corpus of any size trains in bounded time while one recording trains as many epochs as asked."""
    t, data = state.config.train, state.data
    out = []
    for items, batch, epochs, cap in ((data.count("train"), t.batch_ae, t.epochs_ae, t.max_steps_ae),
                                      (data.count("train", t.history, t.include_current), t.batch_lstm,
                                       t.epochs_lstm, t.max_steps_lstm)):
        per_epoch = math.ceil(items / batch)
        out.append(Schedule(per_epoch, min(epochs * per_epoch, cap) if cap > 0 else epochs * per_epoch))
    return out[0], out[1]


def fit(state: TrainState, out: Path, observer: TrainingObserver, progress: Progress, stop: Callable[[], bool]) -> bool:
    """Both phases from wherever `state` stands; False when `stop()` interrupted it."""
    data = state.data
    ae, lstm = schedules(state)
    report = lambda losses: progress(training_step(state), ae.total + lstm.total, losses)  # noqa: E731
    if state.phase == "ae":
        frames = torch.from_numpy(data.frames("train"))  # uint8: a batch becomes float only when used
        test = data.frames("test")

        def ae_loss(index: torch.Tensor) -> torch.Tensor:
            x = frames[index].float()
            return F.binary_cross_entropy_with_logits(state.autoencoder(x), x)

        while state.epoch < ae.epochs:
            loss = run_epoch(state, state.autoencoder, state.ae_optimizer, len(frames), state.config.train.batch_ae,
                             ae, state.config.train.lr_ae, ae_loss, stop)
            if loss is None:
                return False
            end_epoch(state, out, observer, report, loss, ae_test_loss(state, test))
            show_clip(state, observer, imagination=False)
        state.phase, state.epoch = "lstm", 0
        state.make_lstm(*fit_scalers(state, state.codes()))
        state.save(out)
    if state.phase == "lstm":
        x, y = lstm_pairs(state, state.codes(), "train")
        x_val, y_val = lstm_pairs(state, state.codes(), "test")
        while state.epoch < lstm.epochs:
            loss = run_epoch(state, state.lstm, state.lstm_optimizer, len(x), state.config.train.batch_lstm, lstm,
                             state.config.train.lr_lstm, lambda index: F.mse_loss(state.lstm(x[index]), y[index]), stop)
            if loss is None:
                return False
            state.lstm.eval()
            with torch.no_grad():
                val = F.mse_loss(state.lstm(x_val), y_val).item()
            end_epoch(state, out, observer, report, loss, val)
            if state.epoch % 10 == 0 or state.epoch == lstm.epochs:
                show_clip(state, observer, imagination=True)
        state.phase = "done"
    return True


def run_epoch(state: TrainState, model: torch.nn.Module, optimizer: torch.optim.Optimizer, items: int, batch: int,
              schedule: Schedule, base_lr: float, batch_loss: Callable[[torch.Tensor], torch.Tensor],
              stop: Callable[[], bool]) -> Optional[float]:
    """One epoch of either network (cut where the schedule ends): its mean training loss, or None when
    `stop()` interrupted it."""
    model.train()
    order, total, seen = epoch_order(items, state.config.train.seed, 0 if state.phase == "ae" else 1, state.epoch), 0.0, 0
    for i, first in enumerate(range(0, items, batch)):
        step = state.epoch * schedule.steps_per_epoch + i
        if step >= schedule.total:
            break
        for group in optimizer.param_groups:
            group["lr"] = cosine_lr(base_lr, step, schedule.total)
        index = order[first:first + batch]
        loss = batch_loss(index)
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        optimizer.step()
        total += loss.item() * len(index)
        seen += len(index)
        if stop():
            return None
    return total / seen


def end_epoch(state: TrainState, out: Path, observer: TrainingObserver, report: Callable[[dict[str, float]], None],
              train_loss: float, held_out: float) -> None:
    """Count the epoch, keep its losses, save the checkpoint, report to the view and the progress bar."""
    lstm = state.phase != "ae"
    names = ("lstm_train", "lstm_val") if lstm else ("ae_train", "ae_test")
    state.epoch += 1
    for name, value in zip(names, (train_loss, held_out)):
        state.losses[name].append(value)
        observer.loss(name, training_step(state), value)
    state.save(out)
    report(dict(zip(names, (train_loss, held_out))))


def training_step(state: TrainState) -> int:
    """Optimisation steps taken so far over both networks: one axis for every loss curve of the live view."""
    ae, lstm = schedules(state)
    return (min(len(state.losses["ae_train"]) * ae.steps_per_epoch, ae.total)
            + min(len(state.losses["lstm_train"]) * lstm.steps_per_epoch, lstm.total))


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
