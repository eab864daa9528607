"""`softarm train`: the autoencoder on frames, then the LSTM from stretch windows to latents, then metrics.

The loop is written out: shuffle with a generator seeded by (seed, phase, epoch), step through
batches, evaluate on held-out frames, save a checkpoint after every epoch. Because every epoch's
randomness comes from its own seed and the learning rate from the step count, a run resumed from any
epoch's checkpoint ends exactly where an uninterrupted run ends (on the CPU).
"""

import dataclasses
import json
import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional, Protocol, Sequence, Union

import numpy as np
import torch
import torch.nn.functional as F

from softarm import __version__
from softarm.checkpoint import load_checkpoint, save_checkpoint
from softarm.config import Config, config_from_dict
from softarm.dataset import Dataset, load_dataset
from softarm.errors import CheckpointError, OutputError
from softarm.features import Scaler
from softarm.imagine import Imaginer
from softarm.metrics import image_scores, ridge_fit, ridge_predict
from softarm.models import Autoencoder, StretchToLatent
from softarm.outputs import atomic_path, check_outputs

CLIP_FRAMES = 100  # the held-out clip shown each epoch: the first second of the imagination segment


class TrainingObserver(Protocol):
    """What the live view needs; `softarm.viz.TrainingView` implements it (training never imports rerun)."""

    def loss(self, name: str, step: int, value: float) -> None: ...

    def clip(self, epoch: int, times: np.ndarray, truth: np.ndarray, reconstruction: np.ndarray,
             imagination: Optional[np.ndarray]) -> None: ...


Progress = Callable[[str, int, int, dict[str, float]], None]  # (phase, epochs done, epochs in all, losses)


@dataclass(frozen=True)
class TrainResult:
    checkpoint: Path
    metrics_path: Optional[Path]
    metrics: Optional[dict[str, Any]]
    complete: bool
    wall_seconds: float


def check_train_outputs(checkpoint: Path, rrd: Optional[Path], resume: bool, force: bool) -> None:
    """Refuse before any work: a checkpoint that exists (unless resume or force), nothing to resume, bad folders."""
    checkpoint = Path(checkpoint)
    if resume and not checkpoint.exists():
        raise CheckpointError(f"--resume: there is no checkpoint {checkpoint} to continue")
    if checkpoint.exists() and not (resume or force):
        raise OutputError(f"checkpoint {checkpoint} already exists; pass --resume to continue it or --force to replace it")
    check_outputs([checkpoint], force=True)  # folders and permissions; an existing checkpoint is handled above
    if rrd is not None:
        check_outputs([Path(rrd)], force)


def finite_or_null(value: Any) -> Any:
    """NaN (e.g. a tip error where every frame is empty) as null: strict JSON readers reject NaN."""
    if isinstance(value, dict):
        return {k: finite_or_null(v) for k, v in value.items()}
    if isinstance(value, list):
        return [finite_or_null(v) for v in value]
    return None if isinstance(value, float) and not math.isfinite(value) else value


def metrics_path_for(checkpoint: Path) -> Path:
    """The metrics JSON sits beside its checkpoint: model.pt -> model.metrics.json."""
    return checkpoint.with_suffix(".metrics.json")


def cosine_lr(base: float, step: int, total: int) -> float:
    """Cosine decay from base to base/100 over the run: a function of the step alone, so resume is exact."""
    return base * (0.01 + 0.99 * 0.5 * (1 + math.cos(math.pi * min(step, total) / max(total, 1))))


def epoch_order(n: int, seed: int, phase: int, epoch: int) -> torch.Tensor:
    """The shuffle of one epoch, from its own seed: a resumed run shuffles exactly as an uninterrupted one."""
    return torch.randperm(n, generator=torch.Generator().manual_seed(seed * 1_000_003 + phase * 10_007 + epoch))


class Trainer:
    """Owns the networks, optimisers and progress of one training run; `run()` goes to the end."""

    def __init__(self, paths: Sequence[Union[str, Path]], config: Config, out: Path, resume: bool,
                 observer: Optional[TrainingObserver], progress: Optional[Progress]):
        self.config, self.t, self.out = config, config.train, Path(out)
        self.observer, self.progress = observer, progress or (lambda *a: None)
        previous = load_checkpoint(self.out) if resume else None
        if previous is not None:
            saved = config_from_dict(previous["config"])
            ignored = {k: v for k, v in dataclasses.asdict(config.train).items() if getattr(saved.train, k) != v}
            if ignored:
                warnings.warn(f"--resume continues with the saved run's settings; ignored: "
                              + ", ".join(f"train.{k} = {v}" for k, v in ignored.items()), stacklevel=2)
            self.config, self.t = saved, saved.train
        self.data: Dataset = load_dataset(paths, self.t)
        self.height, self.width = self.data.image_shape
        torch.manual_seed(self.t.seed)
        self.ae = Autoencoder(self.height, self.width, self.t.latent)
        self.ae_opt = torch.optim.Adam(self.ae.parameters(), lr=self.t.lr_ae)
        self.lstm: Optional[StretchToLatent] = None
        self.lstm_opt: Optional[torch.optim.Optimizer] = None
        self.latent_scaler = self.stretch_scaler = None
        self._encoded: Optional[list[np.ndarray]] = None  # per-recording latent codes, once the AE is trained
        self.phase, self.epoch = "ae", 0
        self.losses: dict[str, list[float]] = {"ae_train": [], "ae_test": [], "lstm_train": [], "lstm_val": []}
        if previous is not None:
            self._restore(previous)

    # --- checkpoint -------------------------------------------------------------------------------

    def _restore(self, state: dict[str, Any]) -> None:
        fingerprints = [r["sha256"] for r in self.data.fingerprints()]
        if [r["sha256"] for r in state["recordings"]] != fingerprints:
            names = ", ".join(r["name"] for r in state["recordings"])
            raise CheckpointError(f"--resume: {self.out} was trained on other recordings ({names}); "
                                  "give the same recordings in the same order")
        self.ae.load_state_dict(state["autoencoder"])
        self.phase, self.epoch = state["progress"]["phase"], state["progress"]["epoch"]
        self.losses = {k: list(v) for k, v in state["losses"].items()}
        if self.phase == "ae":
            self.ae_opt.load_state_dict(state["optimizer"])
        else:
            self.latent_scaler = Scaler.from_state(state["latent_scaler"])
            self.stretch_scaler = Scaler.from_state(state["stretch_scaler"])
            self._make_lstm()
            self.lstm.load_state_dict(state["lstm"])
            self.lstm_opt.load_state_dict(state["optimizer"])

    def _state(self, metrics: Optional[dict[str, Any]] = None) -> dict[str, Any]:
        state: dict[str, Any] = {
            "softarm_version": __version__, "config": self.config.to_dict(),
            "image_shape": [self.height, self.width], "sensor_count": self.data.sensor_count,
            "recordings": self.data.fingerprints(), "progress": {"phase": self.phase, "epoch": self.epoch},
            "losses": self.losses, "autoencoder": self.ae.state_dict(),
            "lstm": self.lstm.state_dict() if self.lstm is not None else None,
            "optimizer": (self.ae_opt if self.phase == "ae" else self.lstm_opt).state_dict(),
        }
        if self.latent_scaler is not None:
            state["latent_scaler"] = self.latent_scaler.to_state()
            state["stretch_scaler"] = self.stretch_scaler.to_state()
        if metrics is not None:
            state["metrics"] = metrics
        return state

    def _save(self, metrics: Optional[dict[str, Any]] = None) -> None:
        save_checkpoint(self.out, self._state(metrics))

    # --- autoencoder ------------------------------------------------------------------------------

    def _epochs(self, model: torch.nn.Module, optimizer: torch.optim.Optimizer, phase: int, items: int,
                batch: int, epochs: int, base_lr: float, batch_loss: Callable[[torch.Tensor], torch.Tensor],
                after_epoch: Callable[[float], None], stop: Callable[[], bool]) -> bool:
        """The training loop of either network, from self.epoch to `epochs`; False when `stop()` interrupts it."""
        steps_per_epoch = math.ceil(items / batch)
        while self.epoch < epochs:
            model.train()
            order, total = epoch_order(items, self.t.seed, phase, self.epoch), 0.0
            for i, start in enumerate(range(0, items, batch)):
                for group in optimizer.param_groups:
                    group["lr"] = cosine_lr(base_lr, self.epoch * steps_per_epoch + i, epochs * steps_per_epoch)
                index = order[start:start + batch]
                loss = batch_loss(index)
                optimizer.zero_grad(set_to_none=True)
                loss.backward()
                optimizer.step()
                total += loss.item() * len(index)
                if stop():
                    return False
            self.epoch += 1
            after_epoch(total / items)
        return True

    def _train_autoencoder(self, stop: Callable[[], bool]) -> bool:
        frames = torch.from_numpy(self.data.frames("train"))  # uint8: a batch becomes float only when used
        test = torch.from_numpy(self.data.frames("test"))

        def batch_loss(index: torch.Tensor) -> torch.Tensor:
            x = frames[index].float()
            return F.binary_cross_entropy_with_logits(self.ae(x), x)

        def after_epoch(train_loss: float) -> None:
            self._log_epoch("ae", train_loss, self._ae_loss(test))
            self._save()
            self._show_clip(imagination=False)

        if not self._epochs(self.ae, self.ae_opt, 0, len(frames), self.t.batch_ae, self.t.epochs_ae, self.t.lr_ae,
                            batch_loss, after_epoch, stop):
            return False
        self.phase, self.epoch = "lstm", 0
        self._fit_scalers()
        self._make_lstm()
        self._save()
        return True

    @torch.no_grad()
    def _ae_loss(self, frames: torch.Tensor) -> float:
        self.ae.eval()
        total = 0.0
        for i in range(0, len(frames), 512):
            x = frames[i:i + 512].float()
            total += F.binary_cross_entropy_with_logits(self.ae(x), x, reduction="sum").item()
        return total / frames.numel()

    def _codes(self, targets: np.ndarray) -> np.ndarray:
        """Raw latent codes of the (recording, frame) targets, from each recording encoded once.

        Encoding every frame once (16 numbers a frame) replaces stacking copies of the target frames
        for every use: the LSTM's pairs, the scalers, the ridge baseline and the metrics.
        """
        if self._encoded is None:
            self.ae.eval()
            self._encoded = [self._imaginer().encode(seq.frames) for seq in self.data.sequences]
        return np.concatenate([self._encoded[n][targets[targets[:, 0] == n, 1]] for n in range(len(self._encoded))])

    def _fit_scalers(self) -> None:
        """Drop latent features constant over the training frames; normalise with training statistics."""
        train = np.concatenate([np.stack([np.full(b - a, n), np.arange(a, b)], 1)
                                for n, (a, b) in enumerate(s.segment("train") for s in self.data.sequences)])
        self.latent_scaler = Scaler.fit(self._codes(train), self.t.min_feature_std)
        train_stretch = np.concatenate([s.stretch[slice(*s.segment("train"))] for s in self.data.sequences])
        self.stretch_scaler = Scaler.fit(train_stretch)

    # --- LSTM -------------------------------------------------------------------------------------

    def _make_lstm(self) -> None:
        torch.manual_seed(self.t.seed + 1)
        self.lstm = StretchToLatent(self.data.sensor_count, self.t.lstm_hidden, self.latent_scaler.kept)
        self.lstm_opt = torch.optim.Adam(self.lstm.parameters(), lr=self.t.lr_lstm)

    def _lstm_pairs(self, segment: str) -> tuple[torch.Tensor, torch.Tensor]:
        windows, targets = self.data.windows(segment, self.t.history, self.t.include_current)
        latents = self.latent_scaler.forward(self._codes(targets))
        x = self.stretch_scaler.forward(windows).astype(np.float32)
        return torch.from_numpy(x), torch.from_numpy(latents.astype(np.float32))

    def _train_lstm(self, stop: Callable[[], bool]) -> bool:
        x, y = self._lstm_pairs("train")
        x_val, y_val = self._lstm_pairs("test")

        def after_epoch(train_loss: float) -> None:
            self.lstm.eval()
            with torch.no_grad():
                val = F.mse_loss(self.lstm(x_val), y_val).item()
            self._log_epoch("lstm", train_loss, val)
            self._save()
            if self.epoch % 10 == 0 or self.epoch == self.t.epochs_lstm:
                self._show_clip(imagination=True)

        if not self._epochs(self.lstm, self.lstm_opt, 1, len(x), self.t.batch_lstm, self.t.epochs_lstm,
                            self.t.lr_lstm, lambda index: F.mse_loss(self.lstm(x[index]), y[index]),
                            after_epoch, stop):
            return False
        self.phase = "done"
        return True

    # --- metrics ----------------------------------------------------------------------------------

    def _imaginer(self) -> Imaginer:
        self.ae.eval()
        if self.lstm is not None:
            self.lstm.eval()
        return Imaginer(self.ae, self.lstm, self.latent_scaler, self.stretch_scaler, self.t.history,
                        self.t.include_current)

    def evaluate(self) -> dict[str, Any]:
        """Scores on held-out frames: the AE on the test segment; imagination and baselines on the last 5 %."""
        ppm = self.config.camera.pixels_per_metre
        imaginer = self._imaginer()
        test_frames = self.data.frames("test")
        with torch.no_grad():
            test_prob = torch.cat([torch.sigmoid(self.ae(torch.from_numpy(c).float()))
                                   for c in np.array_split(test_frames, max(1, len(test_frames) // 512))]).numpy()
        windows, targets = self.data.windows("imagine", self.t.history, self.t.include_current)
        truth = self.data.target_frames(targets)
        true_latent = self.latent_scaler.forward(self._codes(targets))
        predicted = imaginer.latents(windows)
        train_windows, train_targets = self.data.windows("train", self.t.history, self.t.include_current)
        train_latent = self.latent_scaler.forward(self._codes(train_targets))
        ridge = ridge_fit(self.stretch_scaler.forward(train_windows), train_latent)
        mean_frame = self.data.frames("train").mean(axis=0)
        val_windows, val_targets = self.data.windows("test", self.t.history, self.t.include_current)
        val_latent = self.latent_scaler.forward(self._codes(val_targets))
        return {
            "autoencoder_test": image_scores(test_prob, test_frames, ppm),
            "lstm_latent_mse": {
                "test": float(np.mean((imaginer.latents(val_windows) - val_latent) ** 2)),
                "imagine": float(np.mean((predicted - true_latent) ** 2))},
            "imagination": {
                "lstm": image_scores(imaginer.decode(predicted), truth, ppm),
                "ridge": image_scores(imaginer.decode(ridge_predict(ridge, self.stretch_scaler.forward(windows))),
                                      truth, ppm),
                "mean_frame": image_scores(np.broadcast_to(mean_frame, truth.shape), truth, ppm),
                "ae_ceiling": image_scores(imaginer.decode(true_latent), truth, ppm)},
            "counts": {"train_frames": int(len(self.data.frames("train"))), "test_frames": int(len(test_frames)),
                       "imagination_predictions": int(len(targets)), "kept_latent_features": self.latent_scaler.kept,
                       "latent_features": int(self.t.latent)},
            "recordings": self.data.fingerprints(),
        }

    # --- observer ---------------------------------------------------------------------------------

    def _log_epoch(self, phase: str, train_loss: float, held_out: float) -> None:
        names = ("ae_train", "ae_test") if phase == "ae" else ("lstm_train", "lstm_val")
        for name, value in zip(names, (train_loss, held_out)):
            self.losses[name].append(value)
            if self.observer:
                self.observer.loss(name, len(self.losses[name]), value)
        total = self.t.epochs_ae if phase == "ae" else self.t.epochs_lstm
        self.progress(phase, self.epoch, total, dict(zip(names, (train_loss, held_out))))

    def _show_clip(self, imagination: bool) -> None:
        if self.observer is None:
            return
        seq = self.data.sequences[0]
        start, end = seq.segment("imagine")
        frames = seq.frames[start:min(end, start + CLIP_FRAMES)]
        imaginer = self._imaginer()
        recon = torch.sigmoid(self.ae(torch.from_numpy(frames).float())).detach().numpy()
        imagined = None
        if imagination:
            targets, probs = imaginer.imagine(seq.stretch[start:start + len(frames)])
            imagined = np.zeros_like(recon)
            imagined[targets] = probs
        step = len(self.losses["ae_train"]) + len(self.losses["lstm_train"])
        self.observer.clip(step, seq.times[start:start + len(frames)], frames, recon, imagined)

    # --- the run ----------------------------------------------------------------------------------

    def run(self, stop: Callable[[], bool] = lambda: False) -> bool:
        """Train to the end (True) or until `stop()` says so (False; the last epoch's checkpoint stays)."""
        if self.phase == "ae" and not self._train_autoencoder(stop):
            return False
        if self.phase == "lstm" and not self._train_lstm(stop):
            return False
        return True


def train(paths: Sequence[Union[str, Path]], config: Config, out: Union[str, Path], resume: bool = False,
          observer: Optional[TrainingObserver] = None, progress: Optional[Progress] = None,
          stop: Callable[[], bool] = lambda: False) -> TrainResult:
    """Train (or with resume, continue) on recordings; write the checkpoint and, at the end, its metrics JSON."""
    start = time.perf_counter()
    trainer = Trainer(paths, config, Path(out), resume, observer, progress)
    complete = trainer.run(stop)
    metrics = metrics_file = None
    if complete:
        metrics = trainer.evaluate()
        trainer._save(metrics)
        metrics_file = metrics_path_for(trainer.out)
        with atomic_path(metrics_file) as part:
            part.write_text(json.dumps(finite_or_null(metrics), indent=1, allow_nan=False))
    return TrainResult(trainer.out, metrics_file, metrics, complete, time.perf_counter() - start)
