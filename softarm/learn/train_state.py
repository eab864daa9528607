"""What a training run holds between epochs, and its round trip through a checkpoint file.

The networks, their optimisers, the feature scalers, the phase and epoch reached and the loss
history: everything `--resume` needs to continue exactly where a run stopped, and everything replay
needs to imagine (docs/model.md says what the networks see; `checkpoint` says how the file is kept).
"""

import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Optional, Sequence, Union

import numpy as np
import torch

from softarm import __version__
from softarm.config import Config, load_config, override
from softarm.corpus.manifest import MIN_CORPUS
from softarm.errors import CheckpointError
from softarm.learn.codes import LatentCodes
from softarm.learn.dataset import Dataset, load_dataset
from softarm.learn.node_targets import node_outputs, node_targets
from softarm.model.autoencoder import Autoencoder
from softarm.model.baselines import Baselines
from softarm.model.checkpoint import checkpoint_config, load_checkpoint, save_checkpoint
from softarm.model.device import torch_device
from softarm.model.inputs import Inputs, channels, chosen_inputs
from softarm.model.latent import LatentModel, TrainingSeries
from softarm.model.scaler import Scaler
from softarm.record.reader import read_model
from softarm.registry import latent_model_class
from softarm.trust.surprise import SurpriseModel

REFITTED = ("confidence", "false_alarms_per_minute", "device")  # what --resume always takes from the asked settings:
# the first two are fitted after training, so a finished model sets them anew, and a run continues on the device it
# is given (a checkpoint holds CPU tensors); a larger train.ensemble asked grows its ensemble


@dataclass
class TrainState:
    config: Config
    data: Dataset
    autoencoder: Autoencoder
    ae_optimizer: torch.optim.Optimizer
    latent: Optional[LatentModel] = None   # the network train.model names
    latent_optimizer: Optional[torch.optim.Optimizer] = None
    latent_scaler: Optional[Scaler] = None
    inputs: Optional[Inputs] = None        # the input channels with their scalers
    phase: str = "ae"   # "ae", then "latent", then "members" (an ensemble's others, one after another), then "done"
    epoch: int = 0      # epochs finished in this phase (of the member in training)
    losses: dict[str, list[float]] = field(
        default_factory=lambda: {"ae_train": [], "ae_test": [], "latent_train": [], "latent_val": [],
                                 "members_train": [], "members_val": []})
    members: list[dict[str, torch.Tensor]] = field(default_factory=list)  # finished members' weights
    member: Optional[LatentModel] = None   # the member in training
    member_optimizer: Optional[torch.optim.Optimizer] = None
    surprise: Optional[SurpriseModel] = None
    calibration: Optional[dict[str, Any]] = None   # the calibrated confidence's map (learn/trust_fits.py)
    baselines: Optional[Baselines] = None  # fitted once the model is whole, before the calibration that reads them
    saves: int = 0      # checkpoints this run has written
    device: torch.device = field(default_factory=lambda: torch.device("cpu"))  # where the networks and batches live
    _codes: Optional[LatentCodes] = field(default=None, repr=False)

    def codes(self) -> LatentCodes:
        """Every recording's latent codes, encoded once the autoencoder has finished training."""
        if self.phase == "ae":
            raise RuntimeError("latent codes exist only once the autoencoder is trained")
        if self._codes is None:
            self._codes = LatentCodes(self.autoencoder, self.data)
        return self._codes

    def fit_scalers(self) -> None:
        """Drop latent features constant over the training frames; normalise latents and every input channel
        with training statistics."""
        data = self.data
        self.latent_scaler = Scaler.fit(self.codes().segment(data, "train")[data.seen_frames("train")],
                                        self.config.train.min_feature_std)
        training = np.concatenate([s.inputs[slice(*s.segment("train"))] for s in data.sequences])
        self.inputs = Inputs.fit(data.channels, data.widths, training)

    def make_latent(self) -> None:
        """The latent model and its optimiser, seeded on their own so that resume rebuilds the same network."""
        self.latent, self.latent_optimizer = self._new_latent(self.config.train.seed + 1)

    def next_member(self) -> None:
        """Keep the member just trained (if any) and start the next, or end training when the ensemble is whole."""
        if self.member is not None:
            self.members.append({k: v.detach().clone() for k, v in self.member.state_dict().items()})
        self.epoch, self.member, self.member_optimizer = 0, None, None
        if len(self.members) + 1 >= self.config.train.ensemble:
            self.phase = "done"
            return
        self.phase = "members"
        self.member, self.member_optimizer = self._new_latent(self.config.train.seed + 2 + len(self.members))

    def member_networks(self) -> list[LatentModel]:
        """The finished members, rebuilt from their weights."""
        networks = []
        for weights in self.members:
            network, _ = self._new_latent(0)
            network.load_state_dict(weights)
            networks.append(network)
        return networks

    def _new_latent(self, seed: int) -> tuple[LatentModel, torch.optim.Optimizer]:
        t = self.config.train
        torch.manual_seed(seed)
        network = latent_model_class(t.model)(self.inputs.features, self.latent_scaler.kept, t,
                                              node_outputs(self.data, t.node_target)).to(self.device)
        return network, adam(network.parameters(), t.lr_lstm)

    def training_series(self) -> list[TrainingSeries]:
        """Every recording's normalised inputs and targets (the latent, then the node positions where the model
        has a node head), as the latent model trains on them."""
        codes, data = self.codes(), self.data
        targets = [self.latent_scaler.forward(codes.recording(n)).astype(np.float32)
                   for n in range(len(data.sequences))]
        if self.latent.nodes is not None:
            targets = [np.concatenate([t, nodes], axis=1) for t, nodes in zip(targets, node_targets(data))]
        return [TrainingSeries(self.inputs.normalise(seq.inputs).astype(np.float32), target, seq.segment("train")[1],
                               seq.seen) for seq, target in zip(data.sequences, targets)]

    def to_checkpoint(self, metrics: Optional[dict[str, Any]] = None) -> dict[str, Any]:
        """Plain tensors, numbers and strings: the file loads with torch.load(weights_only=True)."""
        state: dict[str, Any] = {
            "softarm_version": __version__, "config": self.config.to_dict(), "image_shape": list(self.data.image_shape),
            "recordings": self.data.fingerprints(), "progress": {"phase": self.phase, "epoch": self.epoch},
            "losses": self.losses, "autoencoder": self.autoencoder.state_dict(),
            "latent_model": self.latent.state_dict() if self.latent is not None else None,
            "optimizer": {"ae": self.ae_optimizer, "members": self.member_optimizer}.get(self.phase,
                                                                                          self.latent_optimizer).state_dict(),
        }
        if self.members:
            state["members"] = self.members
        if self.member is not None:
            state["member_model"] = self.member.state_dict()
        if self.surprise is not None:
            state["surprise"] = self.surprise.to_state()
        if self.calibration is not None:
            state["calibration"] = self.calibration
        if self.latent_scaler is not None:
            state["latent_scaler"] = self.latent_scaler.to_state()
            state["inputs"] = self.inputs.to_state()
        if metrics is not None:
            state["metrics"] = metrics
        if self.baselines is not None:
            state["baselines"] = self.baselines.to_state()
        return state

    def save(self, path: Path, metrics: Optional[dict[str, Any]] = None) -> None:
        save_checkpoint(path, self.to_checkpoint(metrics))
        self.saves += 1

    def restore(self, saved: dict[str, Any], path: Path) -> None:
        """Continue from a checkpoint of the same recordings (refused otherwise)."""
        if [r["sha256"] for r in saved["recordings"]] != [r["sha256"] for r in self.data.fingerprints()]:
            names = ", ".join(r["name"] for r in saved["recordings"])
            raise CheckpointError(f"--resume: {path} was trained on other recordings ({names}); "
                                  "give the same recordings in the same order")
        self.phase, self.epoch = saved["progress"]["phase"], saved["progress"]["epoch"]
        self.losses.update({k: list(v) for k, v in saved["losses"].items()})
        try:
            self.autoencoder.load_state_dict(saved["autoencoder"])
            if self.phase == "ae":
                self.ae_optimizer.load_state_dict(saved["optimizer"])
                return
            self.latent_scaler, self.inputs = (Scaler.from_state(saved["latent_scaler"]),
                                               Inputs.from_state(saved["inputs"]))
            self.make_latent()
            self.latent.load_state_dict(saved["latent_model"])
            self.members = list(saved.get("members", []))
            if self.phase == "members":
                self.member, self.member_optimizer = self._new_latent(0)
                self.member.load_state_dict(saved["member_model"])
                self.member_optimizer.load_state_dict(saved["optimizer"])
            elif self.phase == "latent":
                self.latent_optimizer.load_state_dict(saved["optimizer"])
        except (RuntimeError, KeyError, TypeError, ValueError) as e:
            raise CheckpointError(f"--resume: {path} does not fit this run's networks ({type(e).__name__}); "
                                  "start afresh with --force") from None


def adam(parameters: Iterable[torch.nn.Parameter], lr: float) -> torch.optim.Adam:
    """Adam in its fused kernel: one pass over all the weights instead of a dozen per tensor, the same update
    (the autoencoder's optimiser step 5.8 -> 1.0 ms on a 2-core CPU)."""
    return torch.optim.Adam(parameters, lr=lr, fused=True)


def start_state(paths: Sequence[Union[str, Path]], config: Config, out: Path, resume: bool,
                stop: Callable[[], bool] = lambda: False,
                read: Callable[[int, int], None] = lambda done, total: None) -> TrainState:
    """A fresh run on `paths`, or with resume the run saved in `out` (whose settings win, with a warning);
    `stop()` is asked between recordings, `read(done, total)` hears of each one read."""
    saved = load_checkpoint(out) if resume else None
    if saved is not None:
        config = _saved_config(saved, config)
    models = [] if config.train.inputs else [read_model(path) for path in paths]
    config = override(config, {"train.inputs": list(chosen_inputs(config.train.inputs, models, config,
                                                                  MIN_CORPUS))})
    t = config.train
    device = torch_device(t.device)  # refused before the recordings are read
    data = load_dataset(paths, config, channels(config.train.inputs), stop, read)
    torch.manual_seed(t.seed)
    autoencoder = Autoencoder(*data.image_shape, t.latent).to(device)
    state = TrainState(config, data, autoencoder, adam(autoencoder.parameters(), t.lr_ae), device=device)
    if saved is not None:
        state.restore(saved, out)
        if state.phase == "done" and len(state.members) + 1 < t.ensemble:
            state.next_member()  # a finished model grows its ensemble
    return state


def _saved_config(saved: dict[str, Any], asked: Config) -> Config:
    """The saved run's config; training and sensing settings asked for now (those that differ from the
    defaults) that differ from it are named and ignored."""
    config = checkpoint_config(saved)
    now, then, default = asked.to_dict(), config.to_dict(), load_config().to_dict()
    asked_now = {f"train.{k}": now["train"][k] for k in REFITTED}
    if now["train"]["ensemble"] > then["train"]["ensemble"]:
        asked_now["train.ensemble"] = now["train"]["ensemble"]
    config = override(config, asked_now)
    then = config.to_dict()
    ignored = [f"{section}.{k} = {v}" for section in ("train", "sensing") for k, v in now[section].items()
               if then[section].get(k) != v and default[section].get(k) != v]
    if ignored:
        warnings.warn("--resume continues with the saved run's settings; ignored: " + ", ".join(ignored), stacklevel=3)
    return config
