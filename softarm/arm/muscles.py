"""Muscles: groups of springs whose rest lengths an activation shortens (docs/model.md, Muscles).

An activation a in [0, 1] of a group sets the rest length of each of its springs to L0 (1 - a c_max); the
activation follows its command u through da/dt = (u - a) / tau, integrated exactly over each substep with u held:
a <- u + (a - u) exp(-h / tau). The Taichi simulator and the NumPy reference both read a `Muscles`.
"""

import math
from dataclasses import dataclass

import numpy as np

from softarm.arm.body import Body
from softarm.config import Config, MuscleGroupConfig
from softarm.config.keys import require
from softarm.errors import ConfigError

SIDES = ("left", "right")


@dataclass(frozen=True)
class Muscles:
    names: tuple[str, ...]
    group: np.ndarray            # (S,) int32: the group of each spring, -1 for a passive one
    max_contraction: np.ndarray  # (G,) share of the rest length a full activation takes off
    time_constant: float         # s

    @property
    def count(self) -> int:
        return len(self.names)

    def rest_lengths(self, body: Body, activation: np.ndarray) -> np.ndarray:
        """(..., S) rest lengths L0 (1 - a c_max) for activations (..., G)."""
        activation = np.asarray(activation, np.float64)
        scale = np.ones(activation.shape[:-1] + (len(self.group),))
        acting = self.group >= 0
        scale[..., acting] = 1.0 - activation[..., self.group[acting]] * self.max_contraction[self.group[acting]]
        return body.rest_lengths * scale

    def relax(self, activation: np.ndarray, command: np.ndarray, h: float) -> np.ndarray:
        """The activation after a step h with the command held (the exact solution of the first-order dynamics)."""
        return command + (activation - command) * math.exp(-h / self.time_constant)


def build_muscles(config: Config, body: Body) -> Muscles:
    """The config's muscle groups as spring masks, every group checked and named in its errors."""
    columns, rows = config.body.columns, config.body.rows
    group = np.full(len(body.springs), -1, np.int32)
    for g, spec in enumerate(config.muscles.groups):
        springs = _springs_of(spec, f"muscles.groups[{g}]", rows, columns, len(body.springs))
        taken = springs[group[springs] >= 0]
        if len(taken):
            raise ConfigError(f"config key 'muscles.groups[{g}]' ({spec.name}) takes spring {int(taken[0])}, which "
                              f"group {config.muscles.groups[group[taken[0]]].name!r} already moves")
        group[springs] = g
    names = tuple(spec.name for spec in config.muscles.groups)
    if len(set(names)) != len(names):
        raise ConfigError(f"config key 'muscles.groups' names {list(names)}: every group needs a name of its own")
    return Muscles(names, group, np.array([s.max_contraction for s in config.muscles.groups], np.float64),
                   config.muscles.time_constant)


def edge_springs(side: str, first: int, last: int, rows: int, columns: int) -> np.ndarray:
    """Indices of the vertical springs of one edge from row `first` down to row `last` (body.py's numbering:
    the horizontal springs first, then the vertical ones row by row)."""
    column = 0 if side == "left" else columns - 1
    return rows * (columns - 1) + np.arange(first, last) * columns + column


def _springs_of(spec: MuscleGroupConfig, key: str, rows: int, columns: int, count: int) -> np.ndarray:
    require("muscles.groups[].max_contraction", spec.max_contraction, f"{key}.max_contraction")
    if (spec.springs is None) == (spec.side is None):
        raise ConfigError(f"config key '{key}' ({spec.name}) needs either side and rows, or springs")
    if spec.springs is not None:
        springs = np.array(spec.springs, np.int64)
        bad = springs[(springs < 0) | (springs >= count)]
        if len(springs) == 0 or len(bad):
            raise ConfigError(f"config key '{key}.springs' = {list(spec.springs)} must name springs 0..{count - 1}")
        return springs
    if spec.side not in SIDES:
        raise ConfigError(f"config key '{key}.side' = {spec.side!r} is out of range: must be one of {list(SIDES)}")
    if spec.rows is None or not 0 <= spec.rows[0] < spec.rows[1] <= rows - 1:
        raise ConfigError(f"config key '{key}.rows' = {spec.rows and list(spec.rows)} must be [first, last] with "
                          f"0 <= first < last <= {rows - 1}")
    return edge_springs(spec.side, spec.rows[0], spec.rows[1], rows, columns)
