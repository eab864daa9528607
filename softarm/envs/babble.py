"""Motor babbling: the arm commanding itself at random and recording what it feels and looks like, so that
`softarm train` can learn its body from its own movements (README, Control).

Each group's command jumps to a new uniform value in [0, 1] after a random hold of `hold` = [min, max] seconds
(its activation smooths the jumps with the muscles' time constant); every episode is one recording.
"""

from pathlib import Path
from typing import Callable, Optional, Sequence, Union

import numpy as np

from softarm.config import Config, load_config, override
from softarm.envs.record import RecordEpisodes
from softarm.envs.single import SoftArmEnv


def babble(folder: Union[str, Path], episodes: int, seconds: float, task: str = "reach",
           config: Optional[Config] = None, hold: Sequence[float] = (0.2, 1.0), seed: int = 0, arch: str = "cpu",
           progress: Optional[Callable[[int], None]] = None) -> list[Path]:
    """Record `episodes` episodes of `seconds` each (episode k from seed seed + k) in `folder`, which must hold no
    episodes yet; returns their paths. `progress(1)` after each."""
    config = override(config if config is not None else load_config(), {"control.episode": seconds})
    env = RecordEpisodes(SoftArmEnv(task, config, arch=arch), folder)
    rng = np.random.default_rng(seed)
    groups = env.unwrapped.arms.muscles.count
    for episode in range(episodes):
        env.reset(seed=seed + episode)
        command = rng.uniform(0, 1, groups)
        change = np.round(rng.uniform(*hold, groups) / config.integration.frame_dt)
        done = False
        while not done:
            change -= 1
            due = change <= 0
            command[due] = rng.uniform(0, 1, int(due.sum()))
            change[due] = np.round(rng.uniform(*hold, int(due.sum())) / config.integration.frame_dt)
            done = any(env.step(command)[2:4])
        if progress is not None:
            progress(1)
    env.close()
    return env.written
