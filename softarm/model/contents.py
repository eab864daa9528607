"""What a checkpoint must hold to be read: every key, type and shape the readers of its state rely on, checked
when it is loaded, so that a damaged or foreign file gets one line instead of a failure deep in torch."""

from pathlib import Path
from typing import Any

import torch

from softarm.errors import CheckpointError

PHASES = ("ae", "latent", "members", "done")


def check_contents(state: dict[str, Any], path: Path) -> None:
    """Refuse a checkpoint state whose structure is not a softarm checkpoint's."""
    def require(ok: bool, what: str) -> None:
        if not ok:
            raise CheckpointError(f"{path} is damaged ({what}): train it again")

    require(isinstance(state.get("config"), dict), "no config")
    shape = state.get("image_shape")
    require(isinstance(shape, list) and len(shape) == 2 and all(_positive_int(n) for n in shape), "image shape")
    progress = state.get("progress")
    require(isinstance(progress, dict) and progress.get("phase") in PHASES and _count(progress.get("epoch")),
            "progress")
    losses = state.get("losses")
    require(isinstance(losses, dict) and all(isinstance(v, list) for v in losses.values()), "losses")
    recordings = state.get("recordings")
    require(isinstance(recordings, list) and all(isinstance(r, dict) and isinstance(r.get("sha256"), str)
                                                 and isinstance(r.get("name"), str) for r in recordings), "recordings")
    require(_tensors(state.get("autoencoder")), "autoencoder weights")
    require(state.get("latent_model") is None or _tensors(state["latent_model"]), "latent model weights")
    if "latent_scaler" in state or state.get("latent_model") is not None:
        require(_scaler(state.get("latent_scaler")), "latent scaler")
        inputs = state.get("inputs")
        require(isinstance(inputs, list) and len(inputs) > 0 and all(
            isinstance(e, dict) and isinstance(e.get("name"), str) and _positive_int(e.get("features"))
            and _scaler(e.get("scaler")) and len(e["scaler"]["mean"]) == e["features"] for e in inputs), "inputs")
    require(isinstance(state.get("members", []), list) and all(_tensors(m) for m in state.get("members", [])),
            "ensemble members")
    require(progress["phase"] != "members" or _tensors(state.get("member_model")), "ensemble member in training")
    require("surprise" not in state or _surprise(state["surprise"]), "surprise model")
    require("calibration" not in state or _calibration(state["calibration"]), "calibrated confidence")
    if "baselines" in state:
        b = state["baselines"]
        require(isinstance(b, dict) and all(isinstance(b.get(k), torch.Tensor)
                                            for k in ("mean_frame", "ridge_weights", "ridge_bias"))
                and list(b["mean_frame"].shape) == shape and b["ridge_weights"].ndim == 2
                and b["ridge_bias"].shape == b["ridge_weights"].shape[1:], "baselines")
        if "node_weights" in b:
            require(isinstance(b["node_weights"], torch.Tensor) and isinstance(b.get("node_bias"), torch.Tensor)
                    and b["node_weights"].ndim == 2 and b["node_bias"].shape == b["node_weights"].shape[1:],
                    "node baseline")


def _surprise(value: Any) -> bool:
    """The forward model's weights (rows: past inputs, command, constant) to the felt sensors, their spreads, the
    map of the expected spread (absent in an earlier softarm's, which `Imaginer` refuses by name), the memory
    check's weights and spreads where there is one, and the alarm's threshold, all finite."""
    if not isinstance(value, dict):
        return False
    try:
        weights, scale = (torch.as_tensor(value["weights"], dtype=torch.float64),
                          torch.as_tensor(value["scale"], dtype=torch.float64))
        spread = torch.as_tensor(value.get("spread", [0.0]), dtype=torch.float64)
        felt, command = list(value["felt"]), list(value["command"])
        threshold = float(value["threshold"])
        memory = value.get("memory", {"weights": value["weights"], "scale": value["scale"]})
        memory = (torch.as_tensor(memory["weights"], dtype=torch.float64),
                  torch.as_tensor(memory["scale"], dtype=torch.float64))
    except (KeyError, IndexError, TypeError, ValueError, RuntimeError, OverflowError):
        return False
    return (all(w.ndim == 2 and s.ndim == 1 and w.shape[1] == len(s) == len(felt) > 0 and w.shape[0] > len(command)
                and bool(torch.isfinite(w).all() and (s > 0).all()) for w, s in ((weights, scale), memory))
            and spread.ndim == 1 and bool(torch.isfinite(spread).all()) and threshold == threshold
            and all(_count(i) for i in felt + command))


def _calibration(value: Any) -> bool:
    if not isinstance(value, dict):
        return False
    try:
        weights, spread = torch.as_tensor(value["weights"], dtype=torch.float64), float(value["spread"])
    except (KeyError, IndexError, TypeError, ValueError, RuntimeError, OverflowError):
        return False
    return weights.ndim == 1 and len(weights) >= 2 and bool(torch.isfinite(weights).all()) and spread >= 0


def _positive_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value > 0


def _count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _tensors(value: Any) -> bool:
    return isinstance(value, dict) and all(isinstance(k, str) and isinstance(v, torch.Tensor) for k, v in value.items())


def _scaler(value: Any) -> bool:
    """keep, mean and std: 1-D tensors of one length."""
    return (isinstance(value, dict) and all(isinstance(value.get(k), torch.Tensor) and value[k].ndim == 1
                                            for k in ("keep", "mean", "std"))
            and len(value["keep"]) == len(value["mean"]) == len(value["std"]))
