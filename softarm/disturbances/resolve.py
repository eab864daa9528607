"""The disturbances of one arm: every [[disturbances]] table of the config, then those its seed draws from each
[[world.random]] spec, in that order (their indices are the ones `/arm/disturbance` names). Every table and spec
is checked, its key named, before any arm is built."""

from typing import Any

import numpy as np

from softarm.config import Config, DisturbanceConfig, RandomDisturbanceConfig
from softarm.disturbances import KINDS, Disturbance
from softarm.disturbances.places import Places

STREAM = 20_170_613  # the draws' own random stream, apart from the drive's (the seed alone) and the sensing's
PARAMETERS = tuple(dict.fromkeys(key for kind in KINDS.values() for key in kind.keys))  # every kind's table keys
DRAWN_BY = tuple(dict.fromkeys(key for kind in KINDS.values() for key in (*kind.drawn_by, *kind.drawn_optional)))


def resolve(config: Config, places: Places, seed: int) -> list[Disturbance]:
    """The arm's disturbances, explicit ones first."""
    explicit = [from_table(table, places.at(f"disturbances[{k}]")) for k, table in enumerate(config.disturbances)]
    drawn = [d for k, spec in enumerate(config.world.random)
             for d in draw(spec, np.random.default_rng([STREAM, seed, k]), places.at(f"world.random[{k}]"))]
    return explicit + drawn


def check_world(config: Config, places: Places) -> None:
    """Every table and spec of the config, checked once for the whole batch."""
    for k, table in enumerate(config.disturbances):
        from_table(table, places.at(f"disturbances[{k}]"))
    for k, spec in enumerate(config.world.random):
        check_spec(spec, places.at(f"world.random[{k}]"))


def kind(name: str, places: Places) -> type[Disturbance]:
    places.require(name in KINDS, "kind", name, f"must be one of {list(KINDS)}")
    return KINDS[name]


def from_table(table: DisturbanceConfig, places: Places) -> Disturbance:
    cls = kind(table.kind, places)
    given = [name for name in PARAMETERS if getattr(table, name) is not None]
    foreign = [name for name in given if name not in cls.keys]
    places.require(not foreign, foreign[0] if foreign else "kind", getattr(table, foreign[0]) if foreign else None,
                   f"a {cls.kind} takes {', '.join(cls.keys)}")
    for name in cls.keys:
        if name not in cls.optional:
            places.present(name, getattr(table, name), f"a {cls.kind} takes {', '.join(cls.keys)}")
    places.require(table.start >= 0, "start", table.start, "must be >= 0 (s from the run's first frame)")
    places.require(table.end is None or table.end > table.start, "end", table.end,
                   f"must be after start = {table.start:g} s (leave it out: to the end of the run)")
    return cls.from_table(table, table.start, table.end, places)


def check_spec(spec: RandomDisturbanceConfig, places: Places) -> None:
    cls = kind(spec.kind, places)
    takes = f"a random {cls.kind} takes count, start, {', '.join(cls.drawn_by)}"
    foreign = [name for name in DRAWN_BY if getattr(spec, name) is not None
               and name not in (*cls.drawn_by, *cls.drawn_optional)]
    places.require(not foreign, foreign[0] if foreign else "kind", getattr(spec, foreign[0]) if foreign else None,
                   takes + (f" (and optionally {', '.join(cls.drawn_optional)})" if cls.drawn_optional else ""))
    places.require(0 <= spec.share <= 1, "share", spec.share, "must be in [0, 1]")
    for name in ("count", "start", "duration", *cls.drawn_by, *cls.drawn_optional):
        value = getattr(spec, name)
        if name in ("count", "start", *cls.drawn_by):
            places.present(name, value, takes)
        if name != "span":
            places.require(value is None or (0 <= value[0] <= value[1]), name, None if value is None else list(value),
                           "must be [min, max] with 0 <= min <= max")
    places.require(spec.duration is None or spec.duration[0] > 0, "duration", spec.duration,
                   "must be longer than 0 s (leave it out: lasting to the end)")
    if spec.rows is not None:
        places.row(spec.rows[1])  # both ends are rows of the body
        places.row(spec.rows[0])
    cls.check_spec(spec, places)


def draw(spec: RandomDisturbanceConfig, rng: np.random.Generator, places: Places) -> list[Disturbance]:
    """What one arm draws from a spec: nothing (with probability 1 - share), or `count` of its kind at random
    times, each lasting `duration` (or to the end)."""
    check_spec(spec, places)
    if rng.random() >= spec.share:
        return []
    cls = KINDS[spec.kind]
    starts = np.sort(rng.uniform(*spec.start, size=int(rng.integers(spec.count[0], spec.count[1] + 1))))
    out: list[Any] = []
    for start in starts.tolist():
        end = start + float(rng.uniform(*spec.duration)) if spec.duration is not None else None
        out.append(cls.draw(spec, rng, start, end, places))
    return out
