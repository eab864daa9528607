"""The native vector env as a Stable-Baselines3 `VecEnv`, so SB3's algorithms train on many arms stepped in one
kernel launch (README, Control). Needs `pip install stable-baselines3`; `softarm` never imports this module itself.

SB3 resets an ended environment within the step that ends it and wants the ended episode's last observation in
`infos[i]["terminal_observation"]`: on a vector env with Gymnasium's default NEXT_STEP autoreset (wrapped or not,
e.g. by `ImaginedBody`), the adapter resets the ended arms at once with `reset(options={"reset_mask": ...})`.
"""

from typing import Any, Optional, Sequence

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from stable_baselines3.common.vec_env import VecEnv


class StableBaselinesVecEnv(VecEnv):
    def __init__(self, env: VectorEnv):
        if env.metadata["autoreset_mode"] != AutoresetMode.NEXT_STEP:
            raise ValueError("the adapter resets ended arms itself: build the vector env with NEXT_STEP autoreset")
        self.env = env
        super().__init__(env.num_envs, env.single_observation_space, env.single_action_space)
        self._actions = np.zeros(env.action_space.shape)

    def reset(self) -> dict[str, np.ndarray]:
        seeds = None if self._seeds[0] is None else [int(s) for s in self._seeds]
        obs, _ = self.env.reset(seed=seeds)
        self._reset_seeds()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self):
        obs, reward, terminated, truncated, info = self.env.step(self._actions)
        done = terminated | truncated
        infos: list[dict[str, Any]] = [{"is_success": bool(terminated[a])} for a in range(self.num_envs)]
        for a in np.flatnonzero(done):
            infos[a]["terminal_observation"] = {key: value[a].copy() for key, value in obs.items()}
            infos[a]["TimeLimit.truncated"] = bool(truncated[a] and not terminated[a])
        if done.any():
            obs, _ = self.env.reset(options={"reset_mask": done})
        return obs, reward.astype(np.float32), done, infos

    def close(self) -> None:
        self.env.close()

    def get_attr(self, attr_name: str, indices: Optional[Sequence[int]] = None) -> list[Any]:
        return [getattr(self.env, attr_name)] * len(self._indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices: Optional[Sequence[int]] = None) -> None:
        setattr(self.env, attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Optional[Sequence[int]] = None, **kwargs: Any) -> list:
        raise NotImplementedError(f"the arms of a native vector env share one object: call env.{method_name} on it")

    def env_is_wrapped(self, wrapper_class: type, indices: Optional[Sequence[int]] = None) -> list[bool]:
        return [False] * len(self._indices(indices))

    def _indices(self, indices: Optional[Sequence[int]]) -> Sequence[int]:
        return range(self.num_envs) if indices is None else indices
