"""What the single env and the vector env share: the config they read, their spaces, the actions they accept."""

from pathlib import Path
from typing import Sequence, Union

import numpy as np
from gymnasium import spaces

from softarm.config import Config, load_config
from softarm.envs.arms import Arms
from softarm.envs.observations import OBSERVATIONS, Observation
from softarm.errors import ConfigError
from softarm.sim.runtime import init_taichi

ConfigLike = Union[Config, str, Path, None]


def start(config: ConfigLike, task: str, arms: int, arch: str) -> Arms:
    """Taichi on the arch asked (the env is the edge a Gymnasium user starts from), then the arms."""
    init_taichi(arch)
    return Arms(config if isinstance(config, Config) else load_config(config), task, arms)


def observations(observe: Sequence[str]) -> list[Observation]:
    unknown = [key for key in observe if key not in OBSERVATIONS]
    if unknown or not observe:
        raise ConfigError(f"observe = {list(observe)}: choose one or more of {list(OBSERVATIONS)}")
    return [OBSERVATIONS[key]() for key in observe]


def observation_space(arms: Arms, observed: list[Observation]) -> spaces.Dict:
    return spaces.Dict({o.key: o.space(arms) for o in observed})


def action_space(arms: Arms) -> spaces.Box:
    """One command per muscle group, in [0, 1]."""
    return spaces.Box(0.0, 1.0, (arms.muscles.count,), np.float32)


def observe(arms: Arms, observed: list[Observation]) -> dict[str, np.ndarray]:
    """Every arm's observation dict, (arms, ...) per key."""
    return {o.key: o.read(arms) for o in observed}


def commands(actions: object, arms: Arms, shape: tuple[int, ...]) -> np.ndarray:
    """Actions as float64 commands of `shape`: a wrong shape or a non-finite value is refused (ValueError, naming
    the groups); finite values outside [0, 1] are clipped to it (documented: README, Control)."""
    a = np.asarray(actions, dtype=np.float64)
    if a.shape != shape:
        raise ValueError(f"the action has shape {a.shape}; this env takes {shape}: one command in [0, 1] per muscle "
                         f"group {list(arms.muscles.names)}" + (" for each arm" if len(shape) > 1 else ""))
    if not np.isfinite(a).all():
        raise ValueError(f"the action holds NaN or infinite commands ({a.ravel()[~np.isfinite(a.ravel())][0]}); "
                         "commands must be finite, in [0, 1]")
    return np.clip(a, 0.0, 1.0).reshape(arms.arms, -1)
