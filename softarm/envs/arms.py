"""A batch of arms under control: muscles commanded, physics stepped in one kernel launch, sensors read, the
task's targets and rewards; the engine of both the single env and the native vector env (README, Control).

Every arm has its own random generator (targets, sensing, the shaking's phase), so arm i of a batch seeded s
runs exactly as a single env seeded s + i, whatever the other arms do.
"""

import dataclasses

import numpy as np

from softarm.arm.body import build_body
from softarm.arm.drive import drive_for_seed
from softarm.arm.muscles import build_muscles
from softarm.arm.sensors import stretch
from softarm.arm.statics import hanging_equilibrium, initial_state
from softarm.config import Config
from softarm.envs.pushes import place_pushes, placeholders
from softarm.envs.sensing import StepSensing
from softarm.envs.tasks import TASKS
from softarm.envs.workspace import reachable, tip_nodes
from softarm.errors import ConfigError
from softarm.sense.imperfections import SensorModel
from softarm.sim.physics import Simulator


class Arms:
    def __init__(self, config: Config, task: str, arms: int):
        if task not in TASKS:
            raise ConfigError(f"task {task!r} is not known: use one of {list(TASKS)}")
        self.config, self.arms, self.dt = config, arms, config.integration.frame_dt
        self.body = build_body(config)
        self.muscles = build_muscles(config, self.body)
        if self.muscles.count == 0:
            raise ConfigError("the control environments need muscles: the config's [[muscles.groups]] is empty")
        self.hanging = hanging_equilibrium(self.body)
        self.tip = tip_nodes(self.body, config.body.columns)
        self.task = TASKS[task](config.control, reachable(config), self.hanging[self.tip].mean(axis=0), arms, self.dt,
                                config.body.rows)
        self.pairs = np.array(config.sensing.pairs or self.body.sensors, int).reshape(-1, 2)
        self.sensing = StepSensing(SensorModel.from_config(config.sensing), arms, len(self.pairs), self.dt)
        excitation = dataclasses.replace(config.excitation, kind="product_of_sines", time_offset=0.0,
                                         amplitude=config.control.shake_amplitude if self.task.shaken else 0.0)
        self.drives = [drive_for_seed(excitation, 0)] * arms
        i = config.integration
        self.sim = Simulator(self.body, self.drives, self.dt, i.substeps, i.blowup_distance,
                             np.repeat(self.hanging[None], arms, 0), np.zeros((arms,) + self.hanging.shape), 1,
                             placeholders(arms, config.body.columns) if self.task.pushed else (), self.muscles)
        self.episode_steps = max(1, round(config.control.episode / self.dt))
        self.rngs = [np.random.default_rng() for _ in range(arms)]
        self.commands = np.zeros((arms, self.muscles.count))
        self.t0 = np.zeros(arms)  # the shaking's phase at each arm's episode start, s
        self.steps, self.held = np.zeros(arms, np.int64), np.zeros(arms, np.int64)
        self.x, self.v = self.sim.state()
        self.activation = np.zeros_like(self.commands)
        self.stretch = np.zeros((arms, len(self.pairs)))
        self.target, self.distance = self.task.target(np.zeros(arms)), np.zeros(arms)
        self._camera = None

    @property
    def sensor_count(self) -> int:
        return len(self.pairs)

    def reset(self, arms: np.ndarray) -> None:
        """Start new episodes for the given arms: the passive hanging arm (on a shaken top, where the top is now),
        muscles relaxed, the task's new draw; the other arms keep their state."""
        if len(arms) == 0:
            return
        offsets = self.sim.time_offset.to_numpy()
        now = self.sim.frame * self.dt
        x = np.empty((len(arms),) + self.hanging.shape)
        v = np.empty_like(x)
        for k, a in enumerate(arms):  # the shaking starts each episode at a phase t0 of its own: t = t0 + time in it
            t0 = self.rngs[a].uniform(0.0, self.config.excitation.offset_range) if self.task.shaken else 0.0
            offsets[a], self.t0[a] = t0 - now, t0
            x[k], v[k] = initial_state(self.hanging, dataclasses.replace(self.drives[a], time_offset=t0))
        self.sim.time_offset.from_numpy(offsets)
        self.commands[arms] = 0.0
        self.sim.command(self.commands)
        self.sim.place(arms, x, v, np.zeros((len(arms), self.muscles.count)))
        self.task.start(arms, self.rngs)
        if self.task.pushed:
            place_pushes(self.sim, self.task, arms, now, self.config.body.columns)
        self.sensing.start(arms, self.rngs)
        self.steps[arms], self.held[arms] = 0, 0
        self._read(arms)

    def step(self, commands: np.ndarray, arms: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Hold the commands (arms, G) for one frame: every arm steps; the given arms are read and scored.
        Returns (reward, terminated, truncated) of every arm (meaningful for the given ones)."""
        self.commands[:] = commands
        self.sim.command(self.commands)
        self.sim.step_block(1)
        self.steps[arms] += 1
        self._read(arms)
        control = self.config.control
        on = self.distance < control.tolerance
        self.held[arms] = np.where(on[arms], self.held[arms] + 1, 0)
        reward = -self.distance / control.reward_scale - ~on  # never above 0: ending early (Reach's success) pays
        terminated = self.task.succeeded(self.held)
        truncated = (self.steps >= self.episode_steps) & ~terminated
        return reward, terminated, truncated

    def displacement(self, arm: int) -> float:
        """The top's displacement along the drive now (m): the shaking of Hold, 0 for a top held still."""
        return float(self.drives[arm].displacement(self.t0[arm] + self.steps[arm] * self.dt))

    def displacements(self) -> np.ndarray:
        """(arms, 1) every arm's `displacement`, m."""
        return np.array([[self.displacement(a)] for a in range(self.arms)])

    def frames(self) -> np.ndarray:
        """(arms, H, W) uint8 camera frames of the arms now (docs/model.md, Camera)."""
        if self._camera is None:
            from softarm.sim.raster import Rasteriser

            self._camera = Rasteriser(self.config.camera, self.body.outline, self.arms, 1)
        return self._camera.render(self.x[:, None], 1)[:, 0].copy()

    def close(self) -> None:
        self.sim.close()

    def _read(self, arms: np.ndarray) -> None:
        if len(arms) == 0:
            return
        x, v = self.sim.state()
        self.x[arms], self.v[arms] = x[arms], v[arms]
        self.activation[arms] = self.sim.activation()[arms]
        ideal = stretch(self.x[arms], self.body.rest, self.pairs)
        self.stretch[arms] = self.sensing.read(ideal, arms, self.steps[arms], [self.rngs[a] for a in arms])
        self.target = self.task.target(self.steps * self.dt)
        self.distance[arms] = np.linalg.norm(self.x[arms][:, self.tip].mean(axis=1) - self.target[arms], axis=1)
