"""Reading a config: the packaged defaults, a user's TOML file over them, then dotted-key overrides.

Unknown keys get a "did you mean", wrong types name the key and the type it needs; the ranges are
checked in `checks`.
"""

import dataclasses
import difflib
import math
import tomllib
import typing
from importlib import resources
from pathlib import Path
from typing import Any, Union

from softarm.config.checks import check_ranges
from softarm.config.schema import Config
from softarm.errors import ConfigError

DEFAULT_CONFIG_TEXT = resources.files("softarm.config").joinpath("default.toml").read_text()


def load_config(path: Union[str, Path, None] = None, overrides: Union[dict[str, Any], None] = None) -> Config:
    """The defaults, updated by the TOML file at `path` (if given), then by dotted-key `overrides`."""
    data = tomllib.loads(DEFAULT_CONFIG_TEXT)
    if path is not None:
        data = merge(data, _read_toml(Path(path)))
    if overrides:
        data = merge(data, nest({k: v for k, v in overrides.items() if v is not None}))
    return config_from_dict(data)


def override(config: Config, overrides: dict[str, Any]) -> Config:
    """A copy of `config` with some dotted keys changed, e.g. `override(config, {"run.seed": 3})`; validated
    like a file."""
    return config_from_dict(merge(config.to_dict(), nest(overrides)))


def config_from_dict(data: dict[str, Any]) -> Config:
    """Build and validate a Config from a nested dict holding every required key."""
    config = _build(Config, data, "")
    check_ranges(config)
    return config


def _read_toml(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise ConfigError(f"config file {path} not found") from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as e:
        raise ConfigError(f"config file {path} cannot be read: {e}") from None
    try:
        return tomllib.loads(text)
    except ValueError as e:  # TOMLDecodeError, or an integer too long to read
        raise ConfigError(f"config file {path} is not valid TOML: {e}") from None


def nest(dotted: dict[str, Any]) -> dict[str, Any]:
    """{"a.b.c": 1} -> {"a": {"b": {"c": 1}}}: dotted override keys as the nested tables of a file."""
    out: dict[str, Any] = {}
    for key, value in dotted.items():
        *tables, name = key.split(".")
        table = out
        for part in tables:
            table = table.setdefault(part, {})
        table[name] = value
    return out


def merge(base: dict[str, Any], update: dict[str, Any]) -> dict[str, Any]:
    merged = dict(base)
    for key, value in update.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            merged[key] = merge(base[key], value)
        else:
            merged[key] = value
    return merged


def _build(cls: type, data: Any, prefix: str) -> Any:
    where = prefix.rstrip(".") or "the config"
    if not isinstance(data, dict):
        raise ConfigError(f"{where} must be a table, got {data!r}")
    hints = typing.get_type_hints(cls)
    names = [f.name for f in dataclasses.fields(cls)]
    for key in data:
        if key not in names:
            close = difflib.get_close_matches(key, names, n=1)
            hint = f" (did you mean '{prefix}{close[0]}'?)" if close else f"; known keys: {', '.join(names)}"
            raise ConfigError(f"unknown config key '{prefix}{key}'{hint}")
    values = {}
    for field in dataclasses.fields(cls):
        if field.name not in data:
            if field.default is dataclasses.MISSING:
                raise ConfigError(f"config key '{prefix}{field.name}' is missing")
            continue
        hint = hints[field.name]
        value = data[field.name]
        if dataclasses.is_dataclass(hint):
            values[field.name] = _build(hint, value, f"{prefix}{field.name}.")
        else:
            values[field.name] = _coerce(value, hint, f"{prefix}{field.name}")
    return cls(**values)


def _coerce(value: Any, hint: Any, key: str) -> Any:
    """Check `value` against a type hint (int, float, str, tuples, Optional) and convert lists to tuples."""
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if dataclasses.is_dataclass(hint):
        return _build(hint, value, f"{key}.")
    if origin is Union:
        return _coerce(value, next(a for a in args if a is not type(None)), key)
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise ConfigError(f"config key '{key}' must be a list, got {value!r}")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_coerce(v, args[0], f"{key}[{i}]") for i, v in enumerate(value))
        if len(value) != len(args):
            raise ConfigError(f"config key '{key}' must be a list of {len(args)} values, got {list(value)!r}")
        return tuple(_coerce(v, a, f"{key}[{i}]") for i, (v, a) in enumerate(zip(value, args)))
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"config key '{key}' must be a number, got {value!r}")
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        if not math.isfinite(number):
            raise ConfigError(f"config key '{key}' must be finite, got {value!r}")
        return number
    if hint is int:
        if isinstance(value, bool) or not (isinstance(value, int) or (isinstance(value, float) and value.is_integer())):
            raise ConfigError(f"config key '{key}' must be an integer, got {value!r}")
        return int(value)
    if hint is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"config key '{key}' must be true or false, got {value!r}")
        return value
    if hint is str:
        if not isinstance(value, str):
            raise ConfigError(f"config key '{key}' must be a string, got {value!r}")
        return value
    raise TypeError(f"unsupported config type {hint!r} for {key}")
