"""What a controller observes, one class per key of the observation dict (README, Control).

Each reads the batch of arms (`softarm.envs.arms.Arms`) after a step and returns (arms, ...) float32 (pixels:
uint8); `tensor` reads the arms of a device env (`softarm.envs.device_arms.DeviceArms`) alike, as a torch tensor on
their device. Lengths are in millimetres, so that the numbers a policy sees are of order one to ten.
"""

from abc import ABC, abstractmethod
from typing import TYPE_CHECKING

import numpy as np
from gymnasium import spaces

if TYPE_CHECKING:
    import torch

    from softarm.envs.arms import Arms
    from softarm.envs.device_arms import DeviceArms

MM = 1000.0
LIMIT = 1000.0  # bounds of the float observations: mm (a node this far from rest has blown up) or m/s


class Observation(ABC):
    key = ""

    @abstractmethod
    def space(self, arms: "Arms") -> spaces.Space:
        """The space of one arm's observation."""

    @abstractmethod
    def read(self, arms: "Arms") -> np.ndarray:
        """Every arm's observation, (arms, ...)."""

    @abstractmethod
    def tensor(self, arms: "DeviceArms") -> "torch.Tensor":
        """Every arm's observation as `read` gives it, a tensor on the arms' device."""


class Stretch(Observation):
    """The stretch sensors as [sensing] reads them (its pairs and imperfections), mm."""
    key = "stretch"

    def space(self, arms: "Arms") -> spaces.Space:
        return spaces.Box(-LIMIT, LIMIT, (arms.sensor_count,), np.float32)

    def read(self, arms: "Arms") -> np.ndarray:
        return (arms.stretch * MM).astype(np.float32)

    def tensor(self, arms: "DeviceArms") -> "torch.Tensor":
        return (arms.stretch * MM).float()


class Activation(Observation):
    """The muscles' activations, in [0, 1] (the state of their first-order dynamics, not the command)."""
    key = "activation"

    def space(self, arms: "Arms") -> spaces.Space:
        return spaces.Box(0.0, 1.0, (arms.muscles.count,), np.float32)

    def read(self, arms: "Arms") -> np.ndarray:
        return np.clip(arms.activation, 0.0, 1.0).astype(np.float32)

    def tensor(self, arms: "DeviceArms") -> "torch.Tensor":
        return arms.activation.clamp(0.0, 1.0).float()


class Target(Observation):
    """The task's target now, relative to where the passive arm's tip hangs, mm."""
    key = "target"

    def space(self, arms: "Arms") -> spaces.Space:
        return spaces.Box(-LIMIT, LIMIT, (2,), np.float32)

    def read(self, arms: "Arms") -> np.ndarray:
        return ((arms.target - arms.task.resting_tip) * MM).astype(np.float32)

    def tensor(self, arms: "DeviceArms") -> "torch.Tensor":
        return ((arms.target - arms.resting_tip) * MM).float()


class Nodes(Observation):
    """Privileged: every node's position relative to the passive hanging arm (mm) and velocity (m/s), (N, 4)."""
    key = "nodes"

    def space(self, arms: "Arms") -> spaces.Space:
        return spaces.Box(-LIMIT, LIMIT, (arms.body.n_nodes, 4), np.float32)

    def read(self, arms: "Arms") -> np.ndarray:
        return np.concatenate([(arms.x - arms.hanging) * MM, arms.v], axis=-1).astype(np.float32)

    def tensor(self, arms: "DeviceArms") -> "torch.Tensor":
        import torch

        return torch.cat([(arms.x - arms.hanging) * MM, arms.v], dim=-1).float()


class Pixels(Observation):
    """The camera frame of docs/model.md (binary, 1 = arm), as the recordings hold it."""
    key = "pixels"

    def space(self, arms: "Arms") -> spaces.Space:
        camera = arms.config.camera
        return spaces.Box(0, 1, (camera.height, camera.width), np.uint8)

    def read(self, arms: "Arms") -> np.ndarray:
        return arms.frames()

    def tensor(self, arms: "DeviceArms") -> "torch.Tensor":
        return arms.frames().clone()  # the rasteriser's buffer is drawn over at the next step


OBSERVATIONS: dict[str, type[Observation]] = {o.key: o for o in (Stretch, Activation, Target, Nodes, Pixels)}
DEFAULT = ("stretch", "activation", "target")
