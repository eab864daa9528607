"""Every latent model, input channel and confidence by the name the config gives it, one line each.

Classes are imported only when used (`latent_model_class`), so the command line and the config check their names
without loading torch; it lies beneath every package, the config's checks included, and imports none of them. A
new model is one class and one line here.
"""

import importlib
from typing import Any

from softarm.errors import ConfigError

LATENT_MODELS = {
    "window": "softarm.model.window:WindowLSTM",    # the paper's LSTM over the last `history` samples
    "stream": "softarm.model.stream:StreamLSTM",    # an LSTM that carries its state through the whole stream
    "gru": "softarm.model.stream:StreamGRU",        # the same with a GRU layer
    "tcn": "softarm.model.tcn:CausalTCN",           # a causal temporal convolution network over the last 2.56 s
}
INPUT_CHANNELS = {
    "stretch": "softarm.model.inputs:Stretch",      # the stretch sensors, read as [sensing] says
    "bend": "softarm.model.inputs:Bend",            # the bend sensors (softarm.sensors), read as [sensing] says
    "drive": "softarm.model.inputs:Drive",          # the motor command: the top's displacement
    "drive_rate": "softarm.model.inputs:DriveRate",  # its rate, by a backward difference
    "activation": "softarm.model.inputs:Activation",  # a commanded arm's muscle activations (softarm.envs)
}

TRUST = {
    "error_head": "softarm.trust.confidence:ErrorHeadTrust",  # the error head's predicted squared error
    "ensemble": "softarm.trust.confidence:EnsembleTrust",      # the members' disagreement (train.ensemble > 1)
    "calibrated": "softarm.trust.confidence:CalibratedTrust",  # the IoU predicted from error, surprise and spread
}


def trust_class(name: str) -> Any:
    """The class `train.confidence` names."""
    return _load(TRUST, name, "config key 'train.confidence'")


def trust_classes() -> list[Any]:
    """Every way of measuring confidence, in the registry's order."""
    return [trust_class(name) for name in TRUST]


def check_inputs(names: list[str]) -> None:
    """Refuse `train.inputs` naming a channel no class answers to, or one twice, without importing any."""
    for name in names:
        _check(INPUT_CHANNELS, name, "config key 'train.inputs'")
    if len(set(names)) != len(names):
        raise ConfigError(f"config key 'train.inputs' = {names!r} names a channel twice")


def check_latent_model(name: str) -> None:
    """Refuse a `train.model` no class answers to, without importing any."""
    _check(LATENT_MODELS, name, "config key 'train.model'")


def latent_model_class(name: str) -> Any:
    """The class `train.model` names."""
    return _load(LATENT_MODELS, name, "config key 'train.model'")


def input_channel_class(name: str) -> Any:
    """The class of an input channel of a checkpoint (or of the config)."""
    return _load(INPUT_CHANNELS, name, "input channel")


def _check(registry: dict[str, str], name: str, what: str) -> None:
    if name not in registry:
        raise ConfigError(f"{what} = {name!r} is out of range: must be one of {list(registry)}")


def _load(registry: dict[str, str], name: str, what: str) -> Any:
    _check(registry, name, what)
    module, _, cls = registry[name].partition(":")
    return getattr(importlib.import_module(module), cls)
