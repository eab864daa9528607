"""The control tasks: where each arm's target is, and when its episode ends (README, Control; [control]).

A task keeps the episode parameters of every arm of a batch; `start` draws them for the arms that begin an
episode, from each arm's own generator. The reward is shared: -distance / reward_scale each step, plus 1 while
the tip is within `tolerance` of the target.
"""

import math

import numpy as np

from softarm.config import ControlConfig


class Task:
    """The base: a target per arm (arms, 2), m, and no end before the episode's time is up."""
    name = ""
    shaken = False  # the top is shaken (the [excitation] drive at control.shake_amplitude) rather than held still

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float):
        self.control, self.places, self.resting_tip = control, places, resting_tip
        self.goal = np.repeat(resting_tip[None], arms, axis=0)

    def start(self, arms: np.ndarray, rngs: list) -> None:
        """New episodes for the given arms."""

    def target(self, time: np.ndarray) -> np.ndarray:
        """(arms, 2) targets at each arm's time into its episode, s."""
        return self.goal

    def succeeded(self, held: np.ndarray) -> np.ndarray:
        """Which arms end their episode in success, given how many steps in a row each has been on target."""
        return np.zeros(len(held), bool)


class Reach(Task):
    """Bring the tip to a reachable place drawn at random and hold it there for control.hold seconds."""
    name = "reach"

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float):
        super().__init__(control, places, resting_tip, arms, frame_dt)
        self.hold_steps = max(1, round(control.hold / frame_dt))
        self.goal = self.goal.copy()

    def start(self, arms: np.ndarray, rngs: list) -> None:
        for a in arms:
            self.goal[a] = self.places[rngs[a].integers(len(self.places))]

    def succeeded(self, held: np.ndarray) -> np.ndarray:
        return held >= self.hold_steps


class Track(Task):
    """Follow a target that goes from one reachable place to another and back every control.track_period."""
    name = "track"

    def __init__(self, control: ControlConfig, places: np.ndarray, resting_tip: np.ndarray, arms: int, frame_dt: float):
        super().__init__(control, places, resting_tip, arms, frame_dt)
        self.ends = np.repeat(self.goal[:, None], 2, axis=1)

    def start(self, arms: np.ndarray, rngs: list) -> None:
        for a in arms:
            self.ends[a] = self.places[rngs[a].integers(len(self.places), size=2)]

    def target(self, time: np.ndarray) -> np.ndarray:
        share = 0.5 * (1.0 - np.cos(2.0 * math.pi * time / self.control.track_period))
        return self.ends[:, 0] + share[:, None] * (self.ends[:, 1] - self.ends[:, 0])


class Hold(Task):
    """Keep the tip where it hangs while the top is shaken sideways."""
    name = "hold"
    shaken = True


TASKS: dict[str, type[Task]] = {task.name: task for task in (Reach, Track, Hold)}
