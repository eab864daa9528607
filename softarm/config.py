"""Run configuration: every constant of the model, read from TOML over the packaged defaults.

The defaults live in one place, `default.toml` beside this module (print it with `softarm config`);
the dataclasses below only say which keys exist and what type each has. A user file names the keys
it changes; unknown keys, wrong types and out-of-range values are refused with a message that names
the key and what is allowed.
"""

import dataclasses
import difflib
import math
import tomllib
import typing
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Union

from softarm.errors import ConfigError

DEFAULT_CONFIG_TEXT = resources.files("softarm").joinpath("default.toml").read_text()


@dataclass(frozen=True)
class BodyConfig:
    rows: int
    columns: int
    length: float
    base_width: float
    tip_width: float
    node_mass: float
    gravity: tuple[float, float]
    driven: Union[tuple[int, ...], None] = None


@dataclass(frozen=True)
class SpringsConfig:
    stiffness: float
    damping: float


@dataclass(frozen=True)
class ExcitationConfig:
    amplitude: float
    frequencies: tuple[float, ...]
    time_offset: float
    offset_range: float
    amplitude_jitter: float


@dataclass(frozen=True)
class SensorsConfig:
    pairs: tuple[tuple[int, int], ...]


@dataclass(frozen=True)
class CameraConfig:
    width: int
    height: int
    pixels_per_metre: float
    origin: tuple[float, float]
    outline: Union[tuple[int, ...], None] = None


@dataclass(frozen=True)
class IntegrationConfig:
    frame_dt: float
    substeps: int
    integrator: str
    blowup_distance: float


@dataclass(frozen=True)
class RunConfig:
    duration: float
    arms: int
    seed: int


@dataclass(frozen=True)
class TrainConfig:
    train_fraction: float
    test_fraction: float
    latent: int
    history: int
    include_current: bool
    epochs_ae: int
    epochs_lstm: int
    batch_ae: int
    batch_lstm: int
    lr_ae: float
    lr_lstm: float
    lstm_hidden: int
    min_feature_std: float
    seed: int


@dataclass(frozen=True)
class Config:
    body: BodyConfig
    springs: SpringsConfig
    excitation: ExcitationConfig
    sensors: SensorsConfig
    camera: CameraConfig
    integration: IntegrationConfig
    run: RunConfig
    train: TrainConfig

    @property
    def n_frames(self) -> int:
        return round(self.run.duration / self.integration.frame_dt)

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dict (lists, no tuples, no unset optional keys): the form written to recordings."""
        return _plain(dataclasses.asdict(self))

    def replace(self, **dotted: Any) -> "Config":
        """A copy with some keys changed, e.g. `replace(**{"run.seed": 3})`; validated like a file."""
        return config_from_dict(_merge(self.to_dict(), _nest(dotted)))


INTEGRATORS = ("symplectic_euler",)
ARCHS = ("cpu", "gpu", "auto")  # Taichi backends a user can ask for


def load_config(path: Union[str, Path, None] = None, overrides: Union[dict[str, Any], None] = None) -> Config:
    """The defaults, updated by the TOML file at `path` (if given), then by dotted-key `overrides`."""
    data = tomllib.loads(DEFAULT_CONFIG_TEXT)
    if path is not None:
        data = _merge(data, _read_toml(Path(path)))
    if overrides:
        data = _merge(data, _nest({k: v for k, v in overrides.items() if v is not None}))
    return config_from_dict(data)


def config_from_dict(data: dict[str, Any]) -> Config:
    """Build and validate a Config from a nested dict holding every required key."""
    config = _build(Config, data, "")
    _check_ranges(config)
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
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"config file {path} is not valid TOML: {e}") from None


def _nest(dotted: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in dotted.items():
        section, _, name = key.rpartition(".")
        out.setdefault(section, {})[name] = value
    return out


def _merge(base: dict[str, Any], update: dict[str, Any]) -> dict[str, Any]:
    merged = dict(base)
    for key, value in update.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            merged[key] = _merge(base[key], value)
        else:
            merged[key] = value
    return merged


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    return value


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
        if not math.isfinite(value):
            raise ConfigError(f"config key '{key}' must be finite, got {value!r}")
        return float(value)
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


def _require(ok: bool, key: str, value: Any, allowed: str) -> None:
    if not ok:
        raise ConfigError(f"config key '{key}' = {value!r} is out of range: {allowed}")


def _check_ranges(c: Config) -> None:
    """Values every simulation needs to be meaningful; node indices are checked against the body."""
    b, e, cam, i, r = c.body, c.excitation, c.camera, c.integration, c.run
    _require(b.rows >= 2, "body.rows", b.rows, "must be at least 2 (one driven row and one free row)")
    _require(b.columns >= 2, "body.columns", b.columns, "must be at least 2")
    for key in ("length", "base_width", "tip_width", "node_mass"):
        value = getattr(b, key)
        _require(value > 0, f"body.{key}", value, "must be > 0")
    _require(c.springs.stiffness > 0, "springs.stiffness", c.springs.stiffness, "must be > 0")
    _require(c.springs.damping >= 0, "springs.damping", c.springs.damping, "must be >= 0")
    _require(e.amplitude >= 0, "excitation.amplitude", e.amplitude, "must be >= 0")
    _require(len(e.frequencies) >= 1, "excitation.frequencies", list(e.frequencies), "must list at least one frequency")
    _require(e.offset_range >= 0, "excitation.offset_range", e.offset_range, "must be >= 0")
    _require(0 <= e.amplitude_jitter < 1, "excitation.amplitude_jitter", e.amplitude_jitter, "must be in [0, 1)")
    _require(len(c.sensors.pairs) >= 1, "sensors.pairs", [], "must list at least one [a, b] node pair")
    for k, (a, bb) in enumerate(c.sensors.pairs):
        _require(a != bb, f"sensors.pairs[{k}]", [a, bb], "a sensor must join two different nodes")
    _require(cam.width >= 1, "camera.width", cam.width, "must be >= 1")
    _require(cam.height >= 1, "camera.height", cam.height, "must be >= 1")
    _require(cam.pixels_per_metre > 0, "camera.pixels_per_metre", cam.pixels_per_metre, "must be > 0")
    _require(i.frame_dt > 0, "integration.frame_dt", i.frame_dt, "must be > 0 (the frame rate is 1 / frame_dt)")
    _require(i.substeps >= 1, "integration.substeps", i.substeps, "must be >= 1")
    _require(i.integrator in INTEGRATORS, "integration.integrator", i.integrator, f"must be one of {list(INTEGRATORS)}")
    _require(i.blowup_distance > 0, "integration.blowup_distance", i.blowup_distance, "must be > 0")
    _require(r.duration > 0, "run.duration", r.duration, "must be > 0")
    _require(c.n_frames >= 1, "run.duration", r.duration, f"must cover at least one frame of {i.frame_dt} s")
    _require(r.arms >= 1, "run.arms", r.arms, "must be >= 1")
    _require(r.seed >= 0, "run.seed", r.seed, "must be >= 0")
    t = c.train
    _require(0 < t.train_fraction < 1, "train.train_fraction", t.train_fraction, "must be in (0, 1)")
    _require(0 < t.test_fraction and t.train_fraction + t.test_fraction < 1, "train.test_fraction",
             t.test_fraction, "must be > 0 and leave room for the imagination segment")
    for key in ("latent", "history", "epochs_ae", "epochs_lstm", "batch_ae", "batch_lstm", "lstm_hidden"):
        _require(getattr(t, key) >= 1, f"train.{key}", getattr(t, key), "must be >= 1")
    for key in ("lr_ae", "lr_lstm"):
        _require(getattr(t, key) > 0, f"train.{key}", getattr(t, key), "must be > 0")
    _require(0 <= t.min_feature_std < 1, "train.min_feature_std", t.min_feature_std, "must be in [0, 1)")
    _require(t.seed >= 0, "train.seed", t.seed, "must be >= 0")
