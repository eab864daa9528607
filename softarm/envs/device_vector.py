"""Many arms as one Gymnasium `VectorEnv` whose observations, actions, rewards, terminations and resets are torch
tensors on one device (docs/reference/environments.md, On a device):

    envs = gymnasium.make_vec("softarm/Reach-v0", num_envs=16_384, device="cuda")

`device` is auto | cpu | cuda (auto: a CUDA GPU where torch sees one); Taichi runs on the same device. Arm i of a
batch seeded s runs as in the NumPy env (`softarm.envs.vector`, which `make_vec` gives without `device`) and as a
single env seeded s + i; what the sensors' white noise and drift draw every step comes from the env's torch
generator instead (seeded by `reset(seed=s)` with s).

Autoreset as the NumPy env: NEXT_STEP by default; with SAME_STEP (what `rsl-rl` and Isaac Lab expect: softarm.envs.
rsl_rl) the ending step returns the first observation of the next episode, and `info["final_obs"]` holds every
arm's observation before the resets, `info["_final_obs"]` the arms that ended.
"""

from typing import Any, Optional, Sequence, Union

import numpy as np
import torch
from gymnasium.error import ClosedEnvironmentError
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from softarm.config import Config, load_config
from softarm.envs.common import ConfigLike, action_space, check_vector, observation_space, observations, reset_mask
from softarm.envs.device_arms import DeviceArms
from softarm.envs.observations import DEFAULT
from softarm.envs.render import colour_view
from softarm.model.device import torch_device
from softarm.sim.runtime import init_taichi


class DeviceVectorEnv(VectorEnv):
    metadata = {"render_modes": ["rgb_array"], "render_fps": 100, "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, task: str = "reach", config: ConfigLike = None,
                 observe: Sequence[str] = DEFAULT, render_mode: Optional[str] = None, device: str = "auto",
                 autoreset_mode: AutoresetMode = AutoresetMode.NEXT_STEP):
        check_vector(num_envs, autoreset_mode)
        self.device = torch_device(str(device))
        init_taichi("gpu" if self.device.type == "cuda" else "cpu")  # the kernels work on the tensors in place
        self.num_envs = num_envs
        self.arms = DeviceArms(config if isinstance(config, Config) else load_config(config), task, num_envs,
                               self.device)
        self.observed = observations(observe)
        self.single_observation_space = observation_space(self.arms.host, self.observed)
        self.single_action_space = action_space(self.arms.host)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": round(1 / self.arms.dt), "autoreset_mode": autoreset_mode}
        self._ended = torch.zeros(num_envs, dtype=torch.bool, device=self.device)
        self._everyone = torch.ones_like(self._ended)
        self._closed = False

    def reset(self, *, seed: Union[int, Sequence[Optional[int]], None] = None,
              options: Optional[dict[str, Any]] = None):
        self._check_open("reset")
        if seed is not None:
            seeds = [seed + a for a in range(self.num_envs)] if isinstance(seed, int) else list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"{len(seeds)} seeds for {self.num_envs} arms")
            for a, s in enumerate(seeds):
                self.arms.rngs[a] = seeding.np_random(s)[0]
            if seeds[0] is not None:
                self.arms.seed(int(seeds[0]))
        mask = (options or {}).get("reset_mask")
        if isinstance(mask, torch.Tensor):
            mask = mask.cpu().numpy()
        arms = np.arange(self.num_envs) if mask is None else np.flatnonzero(reset_mask(mask, self.num_envs))
        self.arms.reset(arms)
        self._ended[torch.as_tensor(arms, device=self.device)] = False
        return self._observe(), self._info()

    def step(self, actions: Union[torch.Tensor, np.ndarray]):
        self._check_open("step")
        u = self._commands(actions)
        if self.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP:
            return self._step_and_reset(u)
        ended = self._ended
        reward, terminated, truncated = self.arms.step(u, ~ended)
        self.arms.reset(ended.nonzero()[:, 0].cpu().numpy())
        reward = torch.where(ended, 0.0, reward)
        terminated, truncated = terminated & ~ended, truncated & ~ended
        self._ended = terminated | truncated
        return self._observe(), reward.float(), terminated, truncated, self._info()

    def _step_and_reset(self, u: torch.Tensor):
        reward, terminated, truncated = self.arms.step(u, self._everyone)
        info = self._info()
        ended = terminated | truncated
        arms = ended.nonzero()[:, 0].cpu().numpy()
        if len(arms):
            info["final_obs"], info["_final_obs"] = self._observe(), ended
            self.arms.reset(arms)
        return self._observe(), reward.float(), terminated, truncated, info

    def render(self) -> Optional[tuple[np.ndarray, ...]]:
        self._check_open("render")
        if self.render_mode != "rgb_array":
            return None
        host, arms = self.arms.host, self.arms
        host.x, host.target, host.distance = (t.cpu().numpy() for t in (arms.x, arms.target, arms.distance))
        return tuple(colour_view(host, a) for a in range(self.num_envs))

    def _commands(self, actions: Union[torch.Tensor, np.ndarray]) -> torch.Tensor:
        """`softarm.envs.common.commands` on the device: float64 (arms, G), a wrong shape or a non-finite value
        refused (ValueError), finite values clipped to [0, 1]."""
        a = torch.as_tensor(actions, device=self.device).detach().to(torch.float64)
        shape = self.action_space.shape
        if tuple(a.shape) != shape:
            raise ValueError(f"the action has shape {tuple(a.shape)}; this env takes {shape}: one command in [0, 1] "
                             f"per muscle group {list(self.arms.muscles.names)} for each arm")
        if not bool(torch.isfinite(a).all()):
            raise ValueError("the action holds NaN or infinite commands; commands must be finite, in [0, 1]")
        return a.clamp(0.0, 1.0)

    def _observe(self) -> dict[str, torch.Tensor]:
        return {o.key: o.tensor(self.arms) for o in self.observed}

    def _check_open(self, call: str) -> None:
        if self._closed:
            raise ClosedEnvironmentError(f"{call}() on a closed environment: its arms are freed; make a new one")

    def close_extras(self, **kwargs: Any) -> None:
        if not self._closed:
            self.arms.close()
            self._closed = True

    def _info(self) -> dict[str, torch.Tensor]:
        a = self.arms
        return {"distance": a.distance.clone(), "_distance": self._everyone,
                "success": a.task.succeeded(a.held), "_success": self._everyone}
