"""Imagination: inputs -> latent model -> normalised latent -> decoder -> frame probabilities.

An `Imaginer` holds the trained networks, the input channels with their scalers and the latent scaler;
training uses it for its metrics, replay and evaluation for whole recordings and the streamer for one
sample at a time, so all of them compute imagination the same way. Raw inputs are normalised once, as
float64, and the latent model reads them as float32.
"""

from dataclasses import dataclass, replace
from typing import Any, Callable, Optional, Sequence

import numpy as np
import torch

from softarm.errors import CheckpointError, RecordingError
from softarm.model.autoencoder import Autoencoder, decode_codes
from softarm.model.baselines import ridge_predict
from softarm.model.checkpoint import checkpoint_config, first_line
from softarm.model.input_windows import input_windows
from softarm.model.inputs import Inputs
from softarm.model.latent import LatentModel
from softarm.model.prediction import Prediction, joined_members
from softarm.model.scaler import Scaler
from softarm.registry import latent_model_class, trust_class
from softarm.trust.confidence import ErrorHeadTrust, Trust
from softarm.trust.surprise import DESIGN, SurpriseModel, feature_width, linear_width


@dataclass
class Imaginer:
    autoencoder: Autoencoder
    latent: LatentModel
    latent_scaler: Scaler
    inputs: Inputs
    members: tuple[LatentModel, ...] = ()      # an ensemble's other members (train.ensemble), beside `latent`
    surprise: Optional[SurpriseModel] = None   # the forward model of the felt stretch (None: not trained)
    trust: Trust = ErrorHeadTrust()            # how the confidence is measured (train.confidence)
    ridge: Optional[tuple[np.ndarray, np.ndarray]] = None  # the ridge baseline (its gap is a confidence feature)

    @classmethod
    def from_checkpoint(cls, state: dict[str, Any], device: Optional[torch.device] = None) -> "Imaginer":
        """Rebuild the networks from a checkpoint's state, on `device` (None: the CPU); refuse one whose weights do
        not fit them."""
        device = device or torch.device("cpu")
        if state.get("latent_model") is None:
            raise CheckpointError("the checkpoint's training stopped before the latent model: finish it with --resume")
        t = checkpoint_config(state).train
        try:
            latent_scaler = Scaler.from_state(state["latent_scaler"])
            inputs = Inputs.from_state(state["inputs"])
        except (KeyError, TypeError, ValueError, RuntimeError):
            raise CheckpointError("the checkpoint's scalers are damaged: train it again") from None
        if inputs.features <= 0 or latent_scaler.kept <= 0 or len(latent_scaler.mean) != t.latent:
            raise CheckpointError("the checkpoint's scalers do not fit its networks: train it again")
        nodes = node_head_outputs(state["latent_model"])
        networks = {"autoencoder": lambda: Autoencoder(*state["image_shape"], t.latent),
                    "latent_model": lambda: latent_model_class(t.model)(inputs.features, latent_scaler.kept, t, nodes)}
        autoencoder, latent = (loaded(make, state[key]).to(device) for key, make in networks.items())
        members = tuple(loaded(networks["latent_model"], weights).to(device).eval()
                        for weights in state.get("members", []))
        autoencoder.eval()
        latent.eval()
        autoencoder.to(memory_format=torch.channels_last)  # faster convolutions when decoding
        surprise = surprise_of(state, inputs.features, t.lstm_hidden)
        trust = trust_class(t.confidence).build(state.get("calibration"))
        if trust is None:
            raise CheckpointError(f"the checkpoint's confidence ({t.confidence}) was not fitted: "
                                  f"finish it with --resume")
        return cls(autoencoder, latent, latent_scaler, inputs, members, surprise, trust, ridge_of(state))

    def normalised(self, raw: np.ndarray) -> np.ndarray:
        """Raw inputs (..., F) as the latent model reads them: normalised, float32."""
        return self.inputs.normalise(raw).astype(np.float32)

    def windows(self, raw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every normalised (float64) window of a raw input series (T, F) and the frame each imagines: the
        frames any model imagines, and what the ridge baseline reads."""
        windows, targets = input_windows(self.inputs.normalise(raw), self.latent.history, self.latent.lead)
        return windows, targets

    def predict(self, raw: np.ndarray) -> Prediction:
        """The latent answer for every frame of a raw input series (T, F) that the model imagines."""
        return self.predict_many([raw])[0]

    def predict_many(self, series: Sequence[np.ndarray]) -> list[Prediction]:
        """`predict` for several series at once (a stream model reads equal-length ones side by side)."""
        for raw in series:
            if len(raw) <= self.latent.first_frame:
                raise RecordingError(f"{len(raw)} input samples are too few for a history of {self.latent.history}")
        exact = [self.inputs.normalise(raw) for raw in series]  # float64, as the ridge baseline reads them
        normalised = [e.astype(np.float32) for e in exact]  # `normalised`: what the networks read
        answers = [model.answer(normalised) for model in (self.latent, *self.members)]
        predictions = [joined_members(parts) for parts in zip(*answers)]
        if self.ridge is not None:
            predictions = [p.with_ridge_gap(self.ridge_answer(e, p.targets)) for p, e in zip(predictions, exact)]
        if self.surprise is None:
            return predictions
        return [p.with_surprise(*(a[p.targets - self.latent.lead]
                                  for a in self.surprise.series(n.astype(np.float64), self.latent.states(n))))
                for p, n in zip(predictions, normalised)]

    def heard_through(self, variance: float) -> "Imaginer":
        """This imaginer for stretch readings that carry `variance` m^2 more white noise per sample than its
        training's: its surprise expects that noise (`SurpriseModel.heard_through`); nothing else changes."""
        if self.surprise is None or variance <= 0.0:
            return self
        felt = list(self.surprise.felt)
        stretch = np.concatenate([np.full(w, c.name == "stretch")
                                  for c, w in zip(self.inputs.channels, self.inputs.widths)])
        added = np.where(stretch[felt], variance / self.inputs.spread[felt] ** 2, 0.0)  # other kinds: not in m
        return replace(self, surprise=self.surprise.heard_through(added))

    @property
    def confidence(self) -> Callable[[Prediction], np.ndarray]:
        """The checkpoint's confidence of a prediction's frames (`train.confidence`)."""
        return self.trust.confidence

    def predict_segments(self, series: Sequence[np.ndarray], bounds: Sequence[tuple[int, int]]) -> Prediction:
        """The answers for one segment [start, end) of each series (targets: (series, frame) pairs)."""
        return self.latent.answer_segments([self.normalised(raw) for raw in series], bounds)

    def ridge_answer(self, normalised: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """(M, K) the ridge baseline's normalised latent for frames `targets` of a normalised float64 series (T, F)."""
        windows, first = input_windows(normalised, self.latent.history, self.latent.lead)
        if len(targets) and (targets[0] < first[0] or targets[-1] > first[-1]):
            raise ValueError(f"frames {targets[0]}..{targets[-1]} have no full input window ({first[0]}..{first[-1]})")
        return self.ridge_latents(windows[targets - first[0]])

    def ridge_latents(self, windows: np.ndarray) -> np.ndarray:
        """(M, K) the ridge baseline's normalised latents for normalised float64 input windows (M, history, F)."""
        return ridge_predict(self.ridge, windows)

    def decode(self, normalised: np.ndarray) -> np.ndarray:
        """Pixel probabilities (M, H, W) of normalised kept latents (M, K)."""
        return decode_codes(self.autoencoder, self.latent_scaler.inverse(normalised))

    def imagine(self, raw: np.ndarray) -> tuple[Prediction, np.ndarray]:
        """The prediction, its pictures drawn (the calibrated confidence reads them), and the imagined pixel
        probabilities (M, H, W) of a whole raw input series (T, F)."""
        prediction = self.predict(raw)
        probabilities = self.decode(prediction.latents)
        return prediction.with_picture(probabilities), probabilities


def surprise_of(state: dict[str, Any], features: int, hidden: int) -> Optional[SurpriseModel]:
    """The checkpoint's surprise model (None without one); refused where an earlier softarm fitted it or it does
    not fit the inputs."""
    if not state.get("surprise"):
        return None
    if not SurpriseModel.current(state["surprise"]):
        raise CheckpointError("the checkpoint's surprise model is of an earlier softarm: refit it (and the "
                              "calibrated confidence) with `softarm train RECORDINGS --out CHECKPOINT --resume`")
    try:
        surprise = SurpriseModel.from_state(state["surprise"])
    except (KeyError, TypeError, ValueError):
        raise CheckpointError("the checkpoint's surprise model is damaged: refit it with `softarm train RECORDINGS "
                              "--out CHECKPOINT --resume`") from None
    memory = surprise.memory
    if (surprise.weights.shape[0] != feature_width(features, len(surprise.command))
            or surprise.precision.shape != (linear_width(features, len(surprise.command)) + 1,) * 2
            or len(surprise.spread) != DESIGN
            or max(surprise.felt + surprise.command) >= features
            or memory is not None and (memory.weights.shape != (hidden + len(surprise.command) + 1, len(surprise.felt))
                                       or memory.scale.shape != surprise.scale.shape)):
        raise CheckpointError("the checkpoint's surprise model does not fit its inputs: train it again")
    return surprise


def ridge_of(state: dict[str, Any]) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """The checkpoint's ridge baseline (weights, bias) as float64, None where it holds no baselines."""
    baselines = state.get("baselines")
    if not isinstance(baselines, dict) or "ridge_weights" not in baselines:
        return None
    return tuple(np.asarray(baselines[key].numpy(), np.float64) for key in ("ridge_weights", "ridge_bias"))


def loaded(make: Callable[[], torch.nn.Module], weights: dict[str, torch.Tensor]) -> torch.nn.Module:
    """The network `make` builds, with `weights`; their shapes are held against it first on torch's meta device,
    where nothing is allocated, so a damaged checkpoint claiming a huge network costs no memory."""
    with torch.device("meta"):
        shapes = {key: tuple(value.shape) for key, value in make().state_dict().items()}
    found = {key: tuple(value.shape) for key, value in weights.items()}
    if shapes != found:
        wrong = sorted(set(shapes) ^ set(found)) or [k for k in shapes if shapes[k] != found[k]]
        raise CheckpointError(f"the checkpoint's weights do not fit this softarm's networks (first: {wrong[0]})")
    network = make()
    try:
        network.load_state_dict(weights)
    except (RuntimeError, TypeError, ValueError) as e:
        raise CheckpointError(f"the checkpoint's weights do not fit this softarm's networks: {first_line(e)}") from None
    return network


def node_head_outputs(weights: Any) -> int:
    """The outputs of a latent model's node head in its weights (`train.node_target`), 0 when it has none."""
    head = weights.get("nodes.weight") if isinstance(weights, dict) else None
    return int(head.shape[0]) if isinstance(head, torch.Tensor) and head.dim() == 2 else 0
