"""Motor babbling: the arm commanding itself at random and recording what it feels and looks like, so that
`softarm train` can learn its body from its own movements (README, Control).

Each group's command jumps to a new uniform value in [0, 1] after a random hold of `hold` = [min, max] seconds
(its activation smooths the jumps with the muscles' time constant); every episode is one recording.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional, Sequence, Union

import numpy as np

from softarm import limits
from softarm.config import Config, load_config, override
from softarm.envs.record import RecordEpisodes
from softarm.envs.single import SoftArmEnv
from softarm.interrupt import Escalated, stop_on_signal
from softarm.sim.budget import footprint


@dataclass(frozen=True)
class Babbled:
    paths: list[Path]   # the episodes written, in order
    complete: bool      # False when a stop request ended it (the episode in progress kept, shorter)


FRAME_BYTES = 84 * 52 + 57 * 2 * 8 * 2 + 64  # an episode's frame held until the episode is written (default sizes)


def babble(folder: Union[str, Path], episodes: int, seconds: float, task: str = "reach",
           config: Optional[Config] = None, hold: Sequence[float] = (0.2, 1.0), seed: int = 0, arch: str = "cpu",
           progress: Optional[Callable[[int], None]] = None) -> Babbled:
    """Record `episodes` episodes of `seconds` each (episode k from seed seed + k) in `folder`, which must hold no
    episodes yet. `progress(1)` after each. Ctrl-C (or SIGTERM, SIGHUP) ends it at the next step: the episode in
    progress is written as it stands (`complete = "false"`) and the result says so; a second request ends it at
    once, with the episodes already written."""
    config = config if config is not None else load_config()
    frame_dt = config.integration.frame_dt
    pixels = config.camera.height * config.camera.width
    limits.seconds("--seconds", seconds, limits.fitting(pixels + FRAME_BYTES) * frame_dt,
                   "of an episode held in memory until it is written")
    episode_bytes = footprint(override(config, {"run.duration": seconds, "run.arms": 1})).disk_bytes
    limits.count("--episodes", episodes, limits.disk_fitting(Path(folder), episode_bytes),
                 f"episodes of {seconds:g} s on the free disk")
    limits.seed("--seed", seed, span=episodes)
    config = override(config, {"control.episode": seconds})
    env = RecordEpisodes(SoftArmEnv(task, config, arch=arch), folder)
    rng = np.random.default_rng(seed)
    groups = env.unwrapped.arms.muscles.count
    with stop_on_signal() as caught:
        try:
            for episode in range(episodes):
                if caught:
                    break
                env.reset(seed=seed + episode)
                command = rng.uniform(0, 1, groups)
                change = np.round(rng.uniform(*hold, groups) / frame_dt)
                done = False
                while not done and not caught:
                    change -= 1
                    due = change <= 0
                    command[due] = rng.uniform(0, 1, int(due.sum()))
                    change[due] = np.round(rng.uniform(*hold, int(due.sum())) / frame_dt)
                    done = any(env.step(command)[2:4])
                if progress is not None and done:
                    progress(1)
            env.close()  # writes an episode cut short, if one is
        except Escalated:
            env.env.close()  # the episode in memory is dropped: a second request wants out now
            raise Escalated(f"stopped at once by a second stop request; {len(env.written)} episode(s) kept in "
                            f"{folder}") from None
    return Babbled(env.written, complete=not caught)
