"""The training loop: the autoencoder on frames, then the latent model from inputs to the frames' codes.

The loop is written out below, top to bottom: shuffle with a generator seeded by (seed, phase,
epoch), step through batches on a cosine learning rate, score held-out frames, save a checkpoint
after every epoch. Because every epoch's randomness comes from its own seed and the learning rate
from the step count, a run resumed from any epoch's checkpoint ends exactly where an uninterrupted
run ends (on the CPU). How a latent model's epoch is cut into steps is the model's own
(`softarm.model.latent.LatentModel.epoch`); the loop is the same for every model.
"""

import math
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Callable, ContextManager, Iterable, Optional

import numpy as np
import torch
import torch.nn.functional as F

from softarm.learn.evaluate import MAX_SCORED, evenly, held_out_mse, imaginer_of
from softarm.learn.observer import NoObserver, Progress, TrainingObserver
from softarm.learn.precision import forward_precision
from softarm.learn.train_state import TrainState
from softarm.model.autoencoder import in_batches, reconstruct
from softarm.model.device import tensor_on
from softarm.model.latent import LatentModel, Step, StepLoss
from softarm.registry import latent_model_class

CLIP_FRAMES = 100  # the held-out clip shown each epoch: the first second of the imagination segment
# A latent model is validated after every VALIDATE_EVERY-th epoch and the last (NaN in the losses between): the
# held-out loss is only reported, never used to choose weights, and reading every recording again after each of
# 150 epochs took 2.6 of 24 minutes. The weights are the same whatever this is (tests/learn/test_validation.py).
VALIDATE_EVERY = 5


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
    latent_steps = latent_model_class(t.model).steps_per_epoch([s.segment("train")[1] for s in data.sequences], t,
                                                               [s.seen for s in data.sequences])
    return tuple(Schedule(per_epoch, min(epochs * per_epoch, cap) if cap > 0 else epochs * per_epoch)
                 for per_epoch, epochs, cap in ((ae_steps, t.epochs_ae, t.max_steps_ae),
                                                (latent_steps, t.epochs_lstm, t.max_steps_lstm)))


def fit(state: TrainState, out: Path, observer: TrainingObserver, progress: Progress, stop: Callable[[], bool]) -> bool:
    """Both phases (and an ensemble's other members) from wherever `state` stands; False when `stop()`
    interrupted it."""
    ae, latent = schedules(state)
    total = ae.total + latent.total * state.config.train.ensemble
    report = lambda done, losses: progress(done, total, losses)  # noqa: E731
    if state.phase == "ae":
        if not fit_autoencoder(state, ae, out, observer, report, stop):
            return False
        state.phase, state.epoch = "latent", 0
        state.fit_scalers()
        state.make_latent()
        state.save(out)
    if state.phase == "latent":
        if not fit_latent(state, state.latent, state.latent_optimizer, latent, ae.total, out, observer, report, stop):
            return False
        state.next_member()
        state.save(out)
    while state.phase == "members":
        before = ae.total + latent.total * (1 + len(state.members))
        if not fit_latent(state, state.member, state.member_optimizer, latent, before, out, observer, report, stop):
            return False
        state.next_member()
        state.save(out)
    return True


Report = Callable[[int, dict[str, float]], None]  # (optimisation steps done over both phases, latest losses)


def fit_autoencoder(state: TrainState, schedule: "Schedule", out: Path, observer: TrainingObserver, report: Report,
                    stop: Callable[[], bool]) -> bool:
    """The autoencoder's epochs, binary cross-entropy on the frames of the training segments."""
    t = state.config.train
    frames = state.data.frames("train").on(state.device)  # packed, on the device: a batch is unpacked there
    test = state.data.frames("test")
    test = test[evenly(len(test), MAX_SCORED)]  # a corpus's held-out loss costs what one recording's does

    def ae_step(index: torch.Tensor) -> StepLoss:
        x = frames[index.to(state.device)].float()
        loss = F.binary_cross_entropy_with_logits(state.autoencoder(x), x)
        return loss, loss.item(), len(index)

    while state.epoch < schedule.epochs:
        batches = shuffled(len(frames), t.batch_ae, t.seed, 0, state.epoch)
        steps = (partial(ae_step, i) for i in batches)
        loss = run_epoch(state.autoencoder, state.ae_optimizer, steps, schedule, state.epoch, t.lr_ae, None,
                         partial(forward_precision, t.precision, state.device.type),
                         lambda i: report(state.epoch * schedule.steps_per_epoch + i, {}), stop)
        if loss is None:
            return False
        with forward_precision(t.precision, state.device.type):  # a reported loss: it may round as the steps do
            held_out = ae_test_loss(state, test)
        end_epoch(state, out, observer, report, loss, held_out)
        show_clip(state, observer, imagination=False)
    return True


def fit_latent(state: TrainState, model: LatentModel, optimizer: torch.optim.Optimizer, schedule: "Schedule",
               before: int, out: Path, observer: TrainingObserver, report: Report, stop: Callable[[], bool]) -> bool:
    """A latent model's epochs (the model's, or an ensemble member's), cut into steps as the model cuts them,
    validated on held-out frames. Members see the epochs in their own shuffles."""
    t = state.config.train
    phase = 2 + len(state.members) if state.phase == "members" else 1  # the shuffle of each member its own
    epoch_steps = model.epoch(state.training_series(), lambda items, epoch: epoch_order(items, t.seed, phase, epoch))
    while state.epoch < schedule.epochs:
        stepped = lambda i: report(before + state.epoch * schedule.steps_per_epoch + i, {})  # noqa: E731
        loss = run_epoch(model, optimizer, epoch_steps(state.epoch), schedule, state.epoch, t.lr_lstm,
                         model.clip_norm, partial(forward_precision, t.precision, state.device.type), stepped, stop)
        if loss is None:
            return False
        held_out = float("nan")
        if (state.epoch + 1) % VALIDATE_EVERY == 0 or state.epoch + 1 == schedule.epochs:
            with forward_precision(t.precision, state.device.type):
                held_out = held_out_mse(imaginer_of(state, model), state.data, state.codes())
        end_epoch(state, out, observer, report, loss, held_out)
        if state.epoch % 10 == 0 or state.epoch == schedule.epochs:
            show_clip(state, observer, imagination=True)
    return True


def run_epoch(network: torch.nn.Module, optimizer: torch.optim.Optimizer, steps: Iterable[Step], schedule: Schedule,
              epoch: int, base_lr: float, clip_norm: Optional[float], precision: Callable[[], ContextManager],
              stepped: Callable[[int], None], stop: Callable[[], bool]) -> Optional[float]:
    """One epoch of either network (cut where the schedule ends): its mean reported loss, or None when
    `stop()` interrupted it. `clip_norm` bounds the gradient norm (recurrent nets need it); each forward pass
    runs in the context `precision()` makes (`softarm.learn.precision`), the backward pass outside it;
    `stepped(i)` hears of every step."""
    params = [p for group in optimizer.param_groups for p in group["params"]]
    network.train()
    total, seen = 0.0, 0
    for i, step_loss in enumerate(steps):
        step = epoch * schedule.steps_per_epoch + i
        if step >= schedule.total:
            break
        for group in optimizer.param_groups:
            group["lr"] = cosine_lr(base_lr, step, schedule.total)
        with precision():
            loss, reported, items = step_loss()
        optimizer.zero_grad(set_to_none=True)
        loss.backward()
        if clip_norm is not None:
            torch.nn.utils.clip_grad_norm_(params, clip_norm)
        optimizer.step()
        total += reported * items
        seen += items
        stepped(i + 1)
        if stop():
            return None
    return total / seen


def end_epoch(state: TrainState, out: Path, observer: TrainingObserver, report: Report, train_loss: float,
              held_out: float) -> None:
    """Count the epoch, keep its losses, save the checkpoint, report to the view and the progress bar."""
    names = {"ae": ("ae_train", "ae_test"), "latent": ("latent_train", "latent_val"),
             "members": ("members_train", "members_val")}[state.phase]
    state.epoch += 1
    latest = {}
    for name, value in zip(names, (train_loss, held_out)):
        state.losses[name].append(value)
        if not math.isnan(value):  # an epoch not validated has no held-out point
            observer.loss(name, training_step(state), value)
            latest[name] = value
    state.save(out)
    report(training_step(state), latest)


def training_step(state: TrainState) -> int:
    """Optimisation steps taken so far over both networks: one axis for every loss curve of the live view."""
    ae, latent = schedules(state)
    member = min(state.epoch * latent.steps_per_epoch, latent.total) if state.phase == "members" else 0
    return (min(len(state.losses["ae_train"]) * ae.steps_per_epoch, ae.total)
            + min(len(state.losses["latent_train"]) * latent.steps_per_epoch, latent.total)
            + latent.total * len(state.members) + member)


@torch.no_grad()
def ae_test_loss(state: TrainState, frames: np.ndarray) -> float:
    """Mean per-pixel BCE of the autoencoder on held-out frames."""
    state.autoencoder.eval()

    def summed(x: torch.Tensor) -> torch.Tensor:
        return F.binary_cross_entropy_with_logits(state.autoencoder(x.float()), x.float(), reduction="sum")[None]

    return float(in_batches(summed, tensor_on(frames, state.device)).double().sum()) / frames.size


def show_clip(state: TrainState, observer: TrainingObserver, imagination: bool) -> None:
    """The first second of the imagination segment: truth | reconstruction | imagination (once the latent model
    learns)."""
    if isinstance(observer, NoObserver):
        return
    seq = state.data.sequences[0]
    start, end = seq.segment("imagine")
    frames = seq.frames[start:min(end, start + CLIP_FRAMES)]
    recon = reconstruct(state.autoencoder.eval(), frames)
    imagined = None
    if imagination:
        imaginer = imaginer_of(state)
        prediction = imaginer.predict(seq.inputs[:start + len(frames)])  # a model with memory reads from the start
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
