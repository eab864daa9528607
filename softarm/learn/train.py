"""The training loop: the autoencoder on frames, then the LSTM from stretch windows to latents.

The loop is written out below, top to bottom: shuffle with a generator seeded by (seed, phase,
epoch), step through batches on a cosine learning rate, score held-out frames, save a checkpoint
after every epoch. Because every epoch's randomness comes from its own seed and the learning rate
from the step count, a run resumed from any epoch's checkpoint ends exactly where an uninterrupted
run ends (on the CPU).
"""

import math
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, Optional

import numpy as np
import torch
import torch.nn.functional as F

from softarm.learn import sequences
from softarm.learn.codes import LatentCodes
from softarm.learn.evaluate import held_out_mse, imaginer_of, reconstruct
from softarm.learn.observer import NoObserver, Progress, TrainingObserver
from softarm.learn.scaler import Scaler
from softarm.learn.train_state import TrainState

CLIP_FRAMES = 100  # the held-out clip shown each epoch: the first second of the imagination segment
CLIP_NORM = 1.0    # the stream model's gradient norm at most



@dataclass(frozen=True)
class Schedule:
    """One phase's optimisation steps: epochs of shuffled batches, cut at `total` steps."""
    steps_per_epoch: int
    total: int

    @property
    def epochs(self) -> int:
        return math.ceil(self.total / self.steps_per_epoch)


def schedules(state: TrainState) -> tuple[Schedule, Schedule]:
    """The autoencoder's and the latent model's: `epochs_*` epochs, at most `max_steps_*` steps (0: no cap),
    so that a corpus of any size trains in bounded time while one recording trains as many epochs as asked."""
    t, data = state.config.train, state.data
    ae_steps = math.ceil(data.count("train") / t.batch_ae)
    lstm_steps = (math.ceil(data.count("train", t.history, t.include_current) / t.batch_lstm) if t.model == "window"
                  else sequences.steps_per_epoch(data, t.streams, t.sequence, t.sequence, lead(state)))
    return tuple(Schedule(per_epoch, min(epochs * per_epoch, cap) if cap > 0 else epochs * per_epoch)
                 for per_epoch, epochs, cap in ((ae_steps, t.epochs_ae, t.max_steps_ae),
                                                (lstm_steps, t.epochs_lstm, t.max_steps_lstm)))


def lead(state: TrainState) -> int:
    return 0 if state.config.train.include_current else 1


def fit(state: TrainState, out: Path, observer: TrainingObserver, progress: Progress, stop: Callable[[], bool]) -> bool:
    """Both phases from wherever `state` stands; False when `stop()` interrupted it."""
    data, t = state.data, state.config.train
    ae, lstm = schedules(state)
    report = lambda losses: progress(training_step(state), ae.total + lstm.total, losses)  # noqa: E731
    if state.phase == "ae":
        frames = torch.from_numpy(data.frames("train"))  # uint8: a batch becomes float only when used
        test = data.frames("test")

        def ae_step(index: torch.Tensor) -> StepLoss:
            x = frames[index].float()
            loss = F.binary_cross_entropy_with_logits(state.autoencoder(x), x)
            return loss, loss.item(), len(index)

        while state.epoch < ae.epochs:
            batches = shuffled(len(frames), t.batch_ae, t.seed, 0, state.epoch)
            loss = run_epoch(state, state.ae_optimizer, (partial(ae_step, i) for i in batches), ae, t.lr_ae, stop)
            if loss is None:
                return False
            end_epoch(state, out, observer, report, loss, ae_test_loss(state, test))
            show_clip(state, observer, imagination=False)
        state.phase, state.epoch = "lstm", 0
        state.make_lstm(*fit_scalers(state, state.codes()))
        state.save(out)
    if state.phase == "lstm":
        epoch_steps = window_steps(state) if t.model == "window" else stream_steps(state)
        while state.epoch < lstm.epochs:
            loss = run_epoch(state, state.lstm_optimizer, epoch_steps(state.epoch), lstm, t.lr_lstm, stop)
            if loss is None:
                return False
            end_epoch(state, out, observer, report, loss, held_out_mse(imaginer_of(state), data, state.codes()))
            if state.epoch % 10 == 0 or state.epoch == lstm.epochs:
                show_clip(state, observer, imagination=True)
        state.phase = "done"
    return True


StepLoss = tuple[torch.Tensor, float, int]  # (loss to minimise, loss to report, items it covers)


def window_steps(state: TrainState) -> Callable[[int], Iterator[Callable[[], StepLoss]]]:
    """An epoch of the window model: shuffled batches of (window, next latent) pairs."""
    t = state.config.train
    x, y = lstm_pairs(state, state.codes(), "train")

    def step(index: torch.Tensor) -> StepLoss:
        mean, log_error = state.lstm(x[index])
        return latent_loss(mean, log_error, y[index])

    return lambda epoch: (partial(step, i) for i in shuffled(len(x), t.batch_lstm, t.seed, 1, epoch))


def stream_steps(state: TrainState) -> Callable[[int], Iterator[Callable[[], StepLoss]]]:
    """An epoch of the stream model: every group of pieces in a shuffled order, each read chunk by chunk
    from a fresh state that carries over (detached) from chunk to chunk."""
    t = state.config.train
    every = sequences.groups(state.data, state.codes(), state.latent_scaler, state.stretch_scaler, t.streams,
                             t.sequence, lead(state))

    def epoch(number: int) -> Iterator[Callable[[], StepLoss]]:
        for g in epoch_order(len(every), t.seed, 1, number).tolist():
            carried: list[Any] = [None]
            for samples, targets, scored in every[g].chunks(t.sequence):
                if not scored.any():
                    with torch.no_grad():
                        carried[0] = state.lstm(samples, carried[0])[2]
                    continue
                yield partial(chunk_step, state.lstm, carried, samples, targets, scored)

    return epoch


def chunk_step(model: torch.nn.Module, carried: list[Any], samples: torch.Tensor, targets: torch.Tensor,
               scored: torch.Tensor) -> StepLoss:
    """One chunk from the carried state, which it then replaces (detached: gradients stop here)."""
    mean, log_error, state = model(samples, carried[0])
    carried[0] = tuple(h.detach() for h in state)
    return latent_loss(mean[scored], log_error[scored], targets[scored])


def latent_loss(mean: torch.Tensor, log_error: torch.Tensor, target: torch.Tensor) -> StepLoss:
    """Mean squared error of the latent, plus the Gaussian negative log-likelihood that teaches the error head
    its own squared error (it reads detached states, so this term leaves the prediction alone)."""
    mse = F.mse_loss(mean, target)
    error = (mean.detach() - target).square()
    return mse + (log_error + error * torch.exp(-log_error)).mean(), mse.item(), len(target)


def run_epoch(state: TrainState, optimizer: torch.optim.Optimizer, steps: Iterable[Callable[[], StepLoss]],
              schedule: Schedule, base_lr: float, stop: Callable[[], bool]) -> Optional[float]:
    """One epoch of either network (cut where the schedule ends): its mean reported loss, or None when
    `stop()` interrupted it. Gradients are clipped to norm CLIP_NORM, which recurrent nets need."""
    params = [p for group in optimizer.param_groups for p in group["params"]]
    (state.autoencoder if state.phase == "ae" else state.lstm).train()
    total, seen = 0.0, 0
    for i, step_loss in enumerate(steps):
        step = state.epoch * schedule.steps_per_epoch + i
        if step >= schedule.total:
            break
        for group in optimizer.param_groups:
            group["lr"] = cosine_lr(base_lr, step, schedule.total)
        loss, reported, items = step_loss()
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        if state.phase != "ae" and state.config.train.model == "stream":
            torch.nn.utils.clip_grad_norm_(params, CLIP_NORM)
        optimizer.step()
        total += reported * items
        seen += items
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
        imaginer = imaginer_of(state)
        prediction = imaginer.predict(seq.stretch[:start + len(frames)])  # the stream model reads from the start
        shown = prediction.take(prediction.targets >= start)
        imagined = np.zeros_like(recon)
        imagined[shown.targets - start] = imaginer.decode(shown.latents)
    observer.clip(training_step(state), seq.times[start:start + len(frames)], frames, recon, imagined)


def cosine_lr(base: float, step: int, total: int) -> float:
    """Cosine decay from base to base/100 over the run: a function of the step alone, so resume is exact."""
    return base * (0.01 + 0.99 * 0.5 * (1 + math.cos(math.pi * min(step, total) / max(total, 1))))


def shuffled(items: int, batch: int, seed: int, phase: int, epoch: int) -> list[torch.Tensor]:
    """The batches of one epoch's shuffle."""
    return list(torch.split(epoch_order(items, seed, phase, epoch), batch))


def epoch_order(n: int, seed: int, phase: int, epoch: int) -> torch.Tensor:
    """The shuffle of one epoch, from its own seed: a resumed run shuffles exactly as an uninterrupted one."""
    return torch.randperm(n, generator=torch.Generator().manual_seed(seed * 1_000_003 + phase * 10_007 + epoch))
