"""The control tasks: where each arm's target is, and when its episode ends (README, Control; [control]).

A task keeps the episode parameters of every arm of a batch; `start` draws them for the arms that begin an
episode, from each arm's own generator. The reward is shared: -distance / reward_scale each step, and -1 more
while the tip is further than `tolerance` from the target (never above 0, so that Reach's early success pays).
"""

import math
from typing import TYPE_CHECKING

import numpy as np

from softarm.config import ControlConfig

if TYPE_CHECKING:
    import torch


class Task:
    """The base: a target per arm (arms, 2), m, and no end before the episode's time is up."""
    name = ""
    shaken = False  # the top is shaken (the [excitation] drive at control.shake_amplitude) rather than held still
    pushed = False  # the arm is pushed once an episode (softarm.envs.pushes)

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float,
                 rows: int):
        self.control, self.places, self.resting_tip, self.rows = control, places, resting_tip, rows
        self.goal = np.repeat(resting_tip[None], arms, axis=0)

    def start(self, arms: np.ndarray, rngs: list) -> None:
        """New episodes for the given arms."""

    def target(self, time: np.ndarray) -> np.ndarray:
        """(arms, 2) targets at each arm's time into its episode, s."""
        return self.goal

    def succeeded(self, held: np.ndarray) -> np.ndarray:
        """Which arms end their episode in success, given how many steps in a row each has been on target."""
        return held < 0  # never (held counts up from 0), on an array or a tensor alike

    def segment(self, arms: np.ndarray) -> np.ndarray:
        """(k, 2, 2) the two places each given arm's target moves between this episode, m (a still target: its
        place twice), so that an env on a device computes every target from them and `progress`."""
        return np.repeat(self.goal[arms][:, None], 2, axis=1)

    def progress(self, time: "torch.Tensor") -> "torch.Tensor":
        """How far along its segment each arm's target is at its time into the episode (a tensor, s), in [0, 1]."""
        return time * 0.0


class Reach(Task):
    """Bring the tip to a reachable place drawn at random and hold it there for control.hold seconds."""
    name = "reach"

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float,
                 rows: int):
        super().__init__(control, places, resting_tip, arms, frame_dt, rows)
        self.hold_steps = max(1, round(control.hold / frame_dt))
        self.goal = self.goal.copy()

    def start(self, arms: np.ndarray, rngs: list) -> None:
        for a in arms:
            self.goal[a] = self.places[rngs[a].integers(len(self.places))]

    def succeeded(self, held: np.ndarray) -> np.ndarray:
        return held >= self.hold_steps  # also on a tensor of held steps


class Track(Task):
    """Follow a target that goes from one reachable place to another and back every control.track_period."""
    name = "track"

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float,
                 rows: int):
        super().__init__(control, places, resting_tip, arms, frame_dt, rows)
        self.ends = np.repeat(self.goal[:, None], 2, axis=1)

    def start(self, arms: np.ndarray, rngs: list) -> None:
        for a in arms:
            self.ends[a] = self.places[rngs[a].integers(len(self.places), size=2)]

    def target(self, time: np.ndarray) -> np.ndarray:
        share = 0.5 * (1.0 - np.cos(2.0 * math.pi * time / self.control.track_period))
        return self.ends[:, 0] + share[:, None] * (self.ends[:, 1] - self.ends[:, 0])

    def segment(self, arms: np.ndarray) -> np.ndarray:
        return self.ends[arms]

    def progress(self, time: "torch.Tensor") -> "torch.Tensor":
        return 0.5 * (1.0 - (2.0 * math.pi * time / self.control.track_period).cos())


class Hold(Task):
    """Keep the tip where it hangs while the top is shaken sideways and, once an episode, a row of the lower
    half is pushed in a random direction (control.push_force per node, for control.push_duration)."""
    name = "hold"
    shaken = True

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float,
                 rows: int):
        super().__init__(control, places, resting_tip, arms, frame_dt, rows)
        self.push_window = np.zeros((arms, 2))  # [start, end) s into the episode
        self.push_force = np.zeros((arms, 2))   # N per node
        self.push_row = np.zeros(arms, int)

    @property
    def pushed(self) -> bool:
        return self.control.push_force[1] > 0

    def start(self, arms: np.ndarray, rngs: list) -> None:
        c = self.control
        for a in arms:
            rng = rngs[a]
            start = rng.uniform(0.25 * c.episode, 0.75 * c.episode)
            self.push_window[a] = start, start + rng.uniform(*c.push_duration)
            magnitude, angle = rng.uniform(*c.push_force), rng.uniform(0, 2 * math.pi)
            self.push_force[a] = magnitude * math.cos(angle), magnitude * math.sin(angle)
            self.push_row[a] = rng.integers(self.rows // 2, self.rows)


TASKS: dict[str, type[Task]] = {task.name: task for task in (Reach, Track, Hold)}
