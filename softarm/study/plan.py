"""A study as data: trials, each a set of dotted config overrides, and which of them `--quick` runs.

A user's study is a TOML file of the same shape as the built-in ones::

    name = "latent"
    variable = "latent features"          # what each trial's value is: the x axis and a table column
    quick = ["latent4", "latent16"]       # optional: the trials --quick runs (default: all)

    [[trials]]
    name = "latent4"                      # letters, digits, - _ . (its checkpoint is trials/<name>.pt)
    value = 4                             # optional (default: the name): where it sits on the x axis
    group = "autoencoder"                 # optional: trials of one group share a line and a panel
    overrides = { "train.latent" = 4 }    # keys of `softarm config`

Every key is checked, and every trial's overrides are checked by load_config, before anything runs.
"""

import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Union

from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.registry import check_inputs, check_latent_model

Value = Union[int, float, str]
STUDY_KEYS = ("name", "variable", "description", "quick", "trials")
TRIAL_KEYS = ("name", "value", "group", "overrides")
NAME = re.compile(r"[A-Za-z0-9_.-]+")


@dataclass(frozen=True)
class Trial:
    name: str
    value: Value
    group: str
    overrides: dict[str, Any]   # dotted config keys, JSON values (lists, not tuples)


@dataclass(frozen=True)
class Study:
    name: str
    variable: str
    description: str
    trials: tuple[Trial, ...]
    quick: tuple[str, ...]      # names of the trials --quick runs

    def quick_trials(self) -> tuple[Trial, ...]:
        return tuple(t for t in self.trials if t.name in self.quick)


def read_study(path: Union[str, Path]) -> Study:
    """The study in a TOML file, every key and override checked; a ConfigError names the first bad one."""
    path = Path(path)
    try:
        document = tomllib.loads(path.read_text())
    except OSError as e:
        raise ConfigError(f"study file {path} cannot be read: {e.strerror}") from None
    except ValueError as e:  # TOMLDecodeError, UnicodeDecodeError, or an integer too long to read
        raise ConfigError(f"study file {path} is not valid TOML: {e}") from None
    return study_from_dict(document, str(path))


def study_from_dict(document: dict[str, Any], where: str) -> Study:
    """A checked Study from the nested dict of a TOML file; `where` names it in errors."""
    _known(document, STUDY_KEYS, "", where)
    name = _string(document, "name", where)
    raw_trials = document.get("trials")
    if not isinstance(raw_trials, list) or not raw_trials or not all(isinstance(t, dict) for t in raw_trials):
        raise ConfigError(f"study {where}: 'trials' must be a non-empty list of tables ([[trials]])")
    trials = tuple(_trial(t, f"trials[{k}]", where) for k, t in enumerate(raw_trials))
    names = [t.name for t in trials]
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:
        raise ConfigError(f"study {where}: two trials are named '{twice}'; every trial needs its own name")
    quick = document.get("quick", names)
    if not isinstance(quick, list) or not all(isinstance(q, str) for q in quick):
        raise ConfigError(f"study {where}: 'quick' must be a list of trial names")
    unknown = next((q for q in quick if q not in names), None)
    if unknown is not None:
        raise ConfigError(f"study {where}: 'quick' names '{unknown}', which is not one of its trials")
    return Study(name, _string(document, "variable", where), str(document.get("description", "")), trials,
                 tuple(quick))


def _trial(table: dict[str, Any], key: str, where: str) -> Trial:
    _known(table, TRIAL_KEYS, f"{key}.", where)
    name = _string(table, "name", where, key)
    if not NAME.fullmatch(name):
        raise ConfigError(f"study {where}: {key}.name '{name}' may hold only letters, digits, '-', '_' and '.'")
    value = table.get("value", name)
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ConfigError(f"study {where}: {key}.value must be a number or a string, got {value!r}")
    overrides = table.get("overrides", {})
    if not isinstance(overrides, dict):
        raise ConfigError(f"study {where}: {key}.overrides must be a table of config keys")
    trial = Trial(name, value, str(table.get("group", "")), flatten(overrides))
    check_overrides(trial.overrides, f"study {where}, trial {name}")
    return trial


def format_value(value: Value) -> str:
    """A trial's value as a tick label or a table cell: 4, 0.5, "upper left"."""
    return f"{value:g}" if isinstance(value, (int, float)) else str(value)


def check_overrides(overrides: dict[str, Any], where: str) -> None:
    """load_config's check of the overrides and the latent model they name, the message prefixed with where they
    come from."""
    try:
        train = load_config(overrides=overrides).train
        check_latent_model(train.model)
        check_inputs(list(train.inputs))
    except ConfigError as e:
        raise ConfigError(f"{where}: {e}") from None


def flatten(table: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """{"train": {"latent": 4}} and {"train.latent": 4} both -> {"train.latent": 4}."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        if isinstance(value, dict):
            out.update(flatten(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def _known(table: dict[str, Any], keys: tuple[str, ...], prefix: str, where: str) -> None:
    unknown = next((k for k in table if k not in keys), None)
    if unknown is not None:
        raise ConfigError(f"study {where}: unknown key '{prefix}{unknown}'; known keys: {', '.join(keys)}")


def _string(table: dict[str, Any], key: str, where: str, prefix: str = "") -> str:
    value = table.get(key)
    if not isinstance(value, str) or not value:
        name = f"{prefix}.{key}" if prefix else key
        raise ConfigError(f"study {where}: '{name}' must be a non-empty string")
    return value
