"""What the single env and the vector env share: the config they read, their spaces, the actions they accept."""

from pathlib import Path
from typing import Sequence, Union

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode

from softarm import limits
from softarm.config import Config, load_config
from softarm.envs.arms import Arms
from softarm.envs.observations import OBSERVATIONS, Observation
from softarm.errors import ConfigError
from softarm.sim.runtime import init_taichi

ConfigLike = Union[Config, str, Path, None]
ARM_BYTES = 16 * 1024  # an arm's memory in an env: its physics state, its readings, observations, its generator


def check_vector(num_envs: object, autoreset_mode: AutoresetMode) -> None:
    """A vector env's arms (a whole number this machine's memory holds) and autoreset mode, refused in words."""
    most = limits.fitting(ARM_BYTES)
    if isinstance(num_envs, bool) or not isinstance(num_envs, int) or not 1 <= num_envs <= most:
        raise ValueError(f"num_envs = {num_envs!r}: give a whole number of arms from 1 to {most:,} (what this "
                         f"machine's available memory holds, about {ARM_BYTES // 1024} kB an arm)")
    if autoreset_mode not in (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP):
        raise ValueError(f"autoreset_mode {autoreset_mode}: this env offers NEXT_STEP and SAME_STEP")


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


def reset_mask(mask: object, arms: int) -> np.ndarray:
    """`options["reset_mask"]` as the boolean array (arms,) it must be: anything else (indices, a scalar, another
    length, NaN) is refused, where reading it as booleans would reset other arms than meant."""
    a = np.asarray(mask)
    if a.dtype != np.bool_ or a.shape != (arms,):
        raise ValueError(f"reset_mask must be a boolean array of shape ({arms},), one entry per arm, True to reset it; "
                         f"got {a.dtype} of shape {a.shape}")
    return a
