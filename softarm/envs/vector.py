"""Many arms as one native Gymnasium `VectorEnv`, stepped in one kernel launch (README, Control):
`gymnasium.make_vec("softarm/Reach-v0", num_envs=256)`.

Autoreset is Gymnasium's default, NEXT_STEP: an arm whose episode ended is reset by the next `step`, which
returns its first observation with reward 0 and ignores its action. With `autoreset_mode=AutoresetMode.SAME_STEP`
(what Stable-Baselines3 expects: softarm.envs.sb3) the ending step resets it and returns its first observation, the
last one of the ended episode in `info["final_obs"]`. `reset(options={"reset_mask": mask})` resets only the arms in
the mask.
"""

from typing import Any, Optional, Sequence, Union

import numpy as np
from gymnasium.error import ClosedEnvironmentError
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from softarm.envs.common import (
    ConfigLike,
    action_space,
    check_vector,
    commands,
    observation_space,
    observations,
    observe,
    reset_mask,
    start,
)
from softarm.envs.observations import DEFAULT
from softarm.envs.render import colour_view


class SoftArmVectorEnv(VectorEnv):
    metadata = {"render_modes": ["rgb_array"], "render_fps": 100, "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, task: str = "reach", config: ConfigLike = None,
                 observe: Sequence[str] = DEFAULT, render_mode: Optional[str] = None, arch: str = "cpu",
                 autoreset_mode: AutoresetMode = AutoresetMode.NEXT_STEP):
        check_vector(num_envs, autoreset_mode)
        self.num_envs = num_envs
        self.arms = start(config, task, num_envs, arch)
        self.observed = observations(observe)
        self.single_observation_space = observation_space(self.arms, self.observed)
        self.single_action_space = action_space(self.arms)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": round(1 / self.arms.dt), "autoreset_mode": autoreset_mode}
        self._ended = np.zeros(num_envs, bool)
        self._closed = False

    def reset(self, *, seed: Union[int, Sequence[Optional[int]], None] = None,
              options: Optional[dict[str, Any]] = None):
        self._check_open("reset")
        everyone = np.arange(self.num_envs)
        if seed is not None:
            seeds = [seed + a for a in range(self.num_envs)] if isinstance(seed, int) else list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"{len(seeds)} seeds for {self.num_envs} arms")
            for a, s in zip(everyone, seeds):
                self.arms.rngs[a] = seeding.np_random(s)[0]
        mask = (options or {}).get("reset_mask")
        arms = everyone if mask is None else np.flatnonzero(reset_mask(mask, self.num_envs))
        self.arms.reset(arms)
        self._ended[arms] = False
        return observe(self.arms, self.observed), self._info()

    def step(self, actions):
        self._check_open("step")
        u = commands(actions, self.arms, self.action_space.shape)
        if self.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP:
            return self._step_and_reset(u)
        ended = np.flatnonzero(self._ended)
        reward, terminated, truncated = self.arms.step(u, np.flatnonzero(~self._ended))
        self.arms.reset(ended)
        reward[ended], terminated[ended], truncated[ended] = 0.0, False, False
        self._ended = terminated | truncated
        return observe(self.arms, self.observed), reward, terminated, truncated, self._info()

    def _step_and_reset(self, u: np.ndarray):
        reward, terminated, truncated = self.arms.step(u, np.arange(self.num_envs))
        info = self._info()
        ended = np.flatnonzero(terminated | truncated)
        if len(ended):
            last = observe(self.arms, self.observed)
            info["final_obs"] = np.full(self.num_envs, None, object)
            info["final_obs"][ended] = [{key: value[a] for key, value in last.items()} for a in ended]
            info["_final_obs"] = terminated | truncated
            self.arms.reset(ended)
        return observe(self.arms, self.observed), reward, terminated, truncated, info

    def render(self) -> Optional[tuple[np.ndarray, ...]]:
        self._check_open("render")
        if self.render_mode != "rgb_array":
            return None
        return tuple(colour_view(self.arms, a) for a in range(self.num_envs))

    def _check_open(self, call: str) -> None:
        if self._closed:
            raise ClosedEnvironmentError(f"{call}() on a closed environment: its arms are freed; make a new one")

    def close_extras(self, **kwargs: Any) -> None:
        if not self._closed:
            self.arms.close()
            self._closed = True

    def _info(self) -> dict[str, np.ndarray]:
        a, every = self.arms, np.ones(self.num_envs, bool)
        return {"distance": a.distance.copy(), "_distance": every,
                "success": a.task.succeeded(a.held), "_success": every}
