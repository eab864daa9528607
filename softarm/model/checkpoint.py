"""Checkpoint files: one torch file of plain tensors, numbers and strings.

Everything in it loads with `torch.load(path, weights_only=True)`: the state dicts, the config, the
input channels with their scalers, the latent feature filter, the fingerprints of the recordings it was
trained on, how far training got (for --resume), the baselines and the metrics. It is written to
`<name>.part` and renamed, so a checkpoint on disk is always whole. A checkpoint of the previous format
(`softarm-checkpoint/1`: the stretch alone, an LSTM) is read as today's.
"""

import warnings
from pathlib import Path
from typing import Any, Union

import torch

from softarm.config import Config, config_from_dict, load_config
from softarm.config.load import merge
from softarm.errors import CheckpointError, SoftarmError
from softarm.files import atomic_path, input_file
from softarm.model.contents import check_contents
from softarm.model.device import on_cpu

FORMAT = "softarm-checkpoint/2"
PREVIOUS = "softarm-checkpoint/1"


def save_checkpoint(path: Union[str, Path], state: dict[str, Any]) -> Path:
    """Write atomically: an interruption leaves the previous epoch's checkpoint, never half of a new one. Every
    tensor is written from the CPU, so the file loads on a machine without the device that trained it."""
    with atomic_path(Path(path)) as part:
        torch.save({"format": FORMAT, **on_cpu(state)}, part)
    return Path(path)


def load_checkpoint(path: Union[str, Path]) -> dict[str, Any]:
    """The checkpoint's contents; a missing, foreign or damaged file raises CheckpointError."""
    path = input_file(path, "checkpoint", CheckpointError)
    with warnings.catch_warnings(record=True) as heard:  # torch warns of what it reads in a foreign file first
        warnings.simplefilter("always")
        try:
            state = torch.load(path, map_location="cpu", weights_only=True)
        except Exception as e:  # a damaged file fails anywhere in torch's unpickler or zip reader, in any way
            raise CheckpointError(f"{path} is not a softarm checkpoint, or is damaged ({type(e).__name__}: "
                                  f"{first_line(e)})") from None
    for warning in heard:  # a file that loads keeps what torch said of it
        warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    if not isinstance(state, dict) or state.get("format") not in (FORMAT, PREVIOUS):
        raise CheckpointError(f"{path} is not a softarm checkpoint (expected format {FORMAT})")
    try:
        state = upgrade(state) if state["format"] == PREVIOUS else state
    except (KeyError, TypeError, AttributeError):
        raise CheckpointError(f"{path} is damaged (its {PREVIOUS} contents are incomplete): train it again") from None
    check_contents(state, path)
    try:
        checkpoint_config(state)
    except SoftarmError as e:
        raise CheckpointError(f"{path} holds a config this softarm cannot read ({' '.join(str(e).split())})") from None
    return state


def first_line(error: BaseException) -> str:
    """The error's message cut to one short line (torch's run over many)."""
    text = str(error).strip()
    return text.splitlines()[0][:120] if text else "unreadable"


def upgrade(old: dict[str, Any]) -> dict[str, Any]:
    """A softarm-checkpoint/1 state as a /2 one: its LSTM is the latent model, its stretch the one input."""
    state = {key: value for key, value in old.items() if key not in ("lstm", "sensor_count", "stretch_scaler")}
    state["format"] = FORMAT
    lstm = old.get("lstm")
    state["latent_model"] = None if lstm is None else {key.replace("lstm.", "rnn.", 1): value
                                                       for key, value in lstm.items()}
    if "stretch_scaler" in old:
        state["inputs"] = [{"name": "stretch", "features": old["sensor_count"], "scaler": old["stretch_scaler"]}]
    phase = old["progress"]["phase"]
    state["progress"] = {**old["progress"], "phase": "latent" if phase == "lstm" else phase}
    state["losses"] = {key.replace("lstm_", "latent_"): value for key, value in old["losses"].items()}
    return state


def checkpoint_config(state: dict[str, Any]) -> Config:
    """The config a checkpoint was trained with, read over today's defaults so that keys added since
    (a checkpoint written before the [sensing] section, say) take their default values."""
    return config_from_dict(merge(load_config().to_dict(), state["config"]))
