"""Ranges every simulation and training needs to be meaningful, with messages that name the key: each key's own
range as `keys.KEYS` declares it, then the rules that tie two keys together."""

import math
from typing import Any

from softarm.config.keys import KEYS, MAX_SEED, require
from softarm.config.schema import Config
from softarm.errors import ConfigError
from softarm.registry import TRUST


def _require(ok: bool, key: str, value: Any, allowed: str) -> None:
    if not ok:
        raise ConfigError(f"config key '{key}' = {value!r} is out of range: {allowed}")


def value_of(config: Config, key: str) -> Any:
    """The value of a dotted key of a section (not of an array table): `value_of(c, "run.seed")`."""
    value: Any = config
    for part in key.split("."):
        value = getattr(value, part)
    return value


def check_ranges(c: Config) -> None:
    """Every key's declared range, then the rules between keys; node indices are checked against the body."""
    direction = c.excitation.direction
    norm = math.hypot(*direction)
    _require(abs(norm - 1) < 1e-9, "excitation.direction", list(direction),
             f"must be a unit vector (its length is {norm:.6g}), e.g. [1.0, 0.0] sideways or [0.0, 1.0] up")
    for key, spec in KEYS.items():
        if spec.rule is not None and "[]" not in key:  # array tables: with the body
            require(key, value_of(c, key))
    _check_pairs(c)
    s = c.excitation.sum_of_sines
    _require(len({len(s.amplitudes), len(s.frequencies), len(s.phases)}) == 1, "excitation.sum_of_sines.amplitudes",
             list(s.amplitudes),
             "amplitudes, frequencies and phases must list one value per component (or all be empty)")
    i, r, t = c.integration, c.run, c.train
    _require(c.n_frames >= 1, "run.duration", r.duration, f"must cover at least one frame of {i.frame_dt} s")
    _require(r.seed <= MAX_SEED - (r.arms - 1), "run.seed", r.seed,
             f"must be in 0..{MAX_SEED - (r.arms - 1)} "
             f"(seeds are 32-bit; arm i of run.arms = {r.arms} uses run.seed + i)")
    k = c.control
    _require(k.hold < k.episode, "control.hold", k.hold, f"must be shorter than control.episode = {k.episode} s")
    _require(t.train_fraction + t.test_fraction < 1, "train.test_fraction", t.test_fraction,
             "must be > 0 and leave room for the imagination segment")
    _require(t.confidence in TRUST, "train.confidence", t.confidence, f"must be one of {list(TRUST)}")  # the registry's
    _require(t.confidence != "ensemble" or t.ensemble > 1, "train.confidence", t.confidence,
             "needs train.ensemble > 1 (members to disagree)")


def _check_pairs(c: Config) -> None:
    for section in (c.sensors, c.sensing):
        name = "sensors" if section is c.sensors else "sensing"
        for k, (a, b) in enumerate(section.pairs):
            _require(a != b, f"{name}.pairs[{k}]", [a, b], "a sensor must join two different nodes")
    s = c.sensing
    if s.pairs:
        _require(s.dropout_sensor < len(s.pairs), "sensing.dropout_sensor", s.dropout_sensor,
                 f"must be -1 or an index into sensing.pairs (0..{len(s.pairs) - 1})")
