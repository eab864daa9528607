"""One arm as a Gymnasium `Env` (README, Control): `gymnasium.make("softarm/Reach-v0")`."""

from typing import Any, Optional, Sequence

import gymnasium
import numpy as np
from gymnasium.error import ClosedEnvironmentError
from gymnasium.utils import seeding

from softarm.envs.common import ConfigLike, action_space, commands, observation_space, observations, observe, start
from softarm.envs.observations import DEFAULT
from softarm.envs.render import colour_view

ONE = np.array([0])


class SoftArmEnv(gymnasium.Env):
    """The arm of docs/model.md with muscles: the action commands each group, the observation is a dict of the
    keys in `observe` (softarm.envs.observations), the task one of softarm.envs.tasks."""
    metadata = {"render_modes": ["rgb_array"], "render_fps": 100}

    def __init__(self, task: str = "reach", config: ConfigLike = None, observe: Sequence[str] = DEFAULT,
                 render_mode: Optional[str] = None, arch: str = "cpu"):
        self.arms = start(config, task, 1, arch)
        self.observed = observations(observe)
        self.observation_space = observation_space(self.arms, self.observed)
        self.action_space = action_space(self.arms)
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": round(1 / self.arms.dt)}
        self._closed = False

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None):
        self._check_open("reset")
        super().reset(seed=seed)
        if seed is None and self._np_random is None:
            self._np_random, self._np_random_seed = seeding.np_random()
        self.arms.rngs[0] = self.np_random
        self.arms.reset(ONE)
        return self._observation(), self._info()

    def step(self, action):
        self._check_open("step")
        reward, terminated, truncated = self.arms.step(commands(action, self.arms, self.action_space.shape), ONE)
        return self._observation(), float(reward[0]), bool(terminated[0]), bool(truncated[0]), self._info()

    def render(self) -> Optional[np.ndarray]:
        self._check_open("render")
        return colour_view(self.arms, 0) if self.render_mode == "rgb_array" else None

    def close(self) -> None:
        if not self._closed:
            self.arms.close()
            self._closed = True

    def _check_open(self, call: str) -> None:
        if self._closed:
            raise ClosedEnvironmentError(f"{call}() on a closed environment: its arm is freed; make a new one")

    def _observation(self) -> dict[str, np.ndarray]:
        return {key: value[0] for key, value in observe(self.arms, self.observed).items()}

    def _info(self) -> dict[str, Any]:
        a = self.arms
        return {"distance": float(a.distance[0]), "success": bool(a.task.succeeded(a.held)[0]),
                "tip": a.x[0, a.tip].mean(axis=0)}
