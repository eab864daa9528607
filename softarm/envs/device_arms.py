"""The batch of arms under control with everything a step touches in torch tensors on one device: the engine of
the device vector env (softarm.envs.device_vector; docs/reference/environments.md, On a device).

The physics is `Arms`'s simulator, stepped by the same kernel; the Taichi kernels read and write the torch tensors
in place (one copy within the device from the simulator's fields to the state tensors, none through the host).
Commands, readings, targets, rewards, step counts and the episode ends are tensors. What an episode start draws
(the target, the shaking's phase, Hold's push, the sensors' bias) comes from each arm's own NumPy generator, in
`Arms`'s order, for the arms that start one: so arm i of a batch seeded s runs exactly as in the NumPy env. The
imperfections drawn every step (white noise, drift) come from one torch generator on the device instead: the same
distributions, other draws.
"""

import dataclasses
from typing import Optional

import numpy as np
import torch

from softarm.arm.statics import initial_state
from softarm.config import Config
from softarm.envs.arms import Arms
from softarm.envs.pushes import place_pushes
from softarm.sim.capacity import raise_on_blowup


class DeviceArms:
    def __init__(self, config: Config, task: str, arms: int, device: torch.device):
        self.host = Arms(config, task, arms)
        h = self.host
        self.config, self.arms, self.dt, self.device = config, arms, h.dt, device
        self.body, self.muscles, self.task, self.sim, self.rngs = h.body, h.muscles, h.task, h.sim, h.rngs
        self.episode_steps, self.sensor_count = h.episode_steps, h.sensor_count
        f64 = dict(dtype=torch.float64, device=device)
        n, groups, sensors = self.body.n_nodes, self.muscles.count, h.sensor_count
        self._status = torch.full((arms, 2), -1, dtype=torch.int32, device=device)  # the kernel's blow-ups
        self.sim.keep_on_device(torch.zeros((arms, 1, n, 2), **f64), self._status)
        self.x, self.v = torch.zeros((arms, n, 2), **f64), torch.zeros((arms, n, 2), **f64)
        self.activation, self.commands = torch.zeros((arms, groups), **f64), torch.zeros((arms, groups), **f64)
        self._fresh = (torch.zeros_like(self.x), torch.zeros_like(self.v), torch.zeros_like(self.activation))
        self.stretch = torch.zeros((arms, sensors), **f64)
        self.target, self.distance = torch.zeros((arms, 2), **f64), torch.zeros(arms, **f64)
        self.steps = torch.zeros(arms, dtype=torch.int64, device=device)
        self.held = torch.zeros_like(self.steps)
        self.hanging = torch.as_tensor(h.hanging, **f64)
        self.resting_tip = torch.as_tensor(self.task.resting_tip, **f64)
        self.tip = torch.as_tensor(h.tip, device=device)
        pairs = h.pairs
        self.pair_ends = torch.as_tensor(pairs, device=device)
        self.pair_rest = torch.as_tensor(np.linalg.norm(self.body.rest[pairs[:, 0]] - self.body.rest[pairs[:, 1]],
                                                        axis=-1), **f64)
        self.ends = torch.as_tensor(self.task.segment(np.arange(arms)), **f64)
        self.sensing = DeviceSensing(h.sensing.model, arms, sensors, self.dt, device)
        self.generator = torch.Generator(device=device)
        self._offsets = np.zeros(arms)  # the shaking's time offset of each arm on the run's clock, s
        self._still = initial_state(h.hanging, h.drives[0])  # the start of an arm whose top is held still
        self._camera: Optional[object] = None

    def seed(self, seed: int) -> None:
        """Seed the torch generator of the per-step draws (the episodes' draws follow the arms' generators)."""
        self.generator.manual_seed(seed)

    def reset(self, arms: np.ndarray) -> None:
        """`Arms.reset` for the given arms (host indices): new episodes drawn from their generators, their states
        placed on the device; the other arms keep theirs."""
        if len(arms) == 0:
            return
        h, now = self.host, self.sim.frame * self.dt
        x = np.empty((len(arms),) + h.hanging.shape)
        v = np.empty_like(x)
        for k, a in enumerate(arms):  # as Arms.reset: each episode's shaking starts at a phase t0 of its own
            t0 = self.rngs[a].uniform(0.0, self.config.excitation.offset_range) if self.task.shaken else 0.0
            self._offsets[a], h.t0[a] = t0 - now, t0
            x[k], v[k] = (initial_state(h.hanging, dataclasses.replace(h.drives[a], time_offset=t0))
                          if self.task.shaken else self._still)
        if self.task.shaken:
            self.sim.time_offset.from_numpy(self._offsets)
        index = torch.as_tensor(arms, device=self.device)
        self.commands[index] = 0.0
        self.sim.command_from(self.commands)
        self.sim.place_on_device(index.to(torch.int32), torch.as_tensor(x, device=self.device),
                                 torch.as_tensor(v, device=self.device))
        self.task.start(arms, self.rngs)
        self.ends[index] = torch.as_tensor(self.task.segment(arms), dtype=torch.float64, device=self.device)
        if self.task.pushed:
            place_pushes(self.sim, self.task, arms, now, self.config.body.columns)
        h.sensing.start(arms, self.rngs)
        self.sensing.start(index, torch.as_tensor(h.sensing.bias[arms], device=self.device))
        self.steps[index], self.held[index] = 0, 0
        mask = torch.zeros(self.arms, dtype=torch.bool, device=self.device)
        mask[index] = True
        self._read(mask)

    def step(self, commands: torch.Tensor, live: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """`Arms.step`: hold the commands (arms, G) float64 for one frame; every arm steps, the `live` ones (a
        boolean mask) are read and scored. Returns (reward float64, terminated, truncated) of every arm."""
        self.commands.copy_(commands)
        self.sim.command_from(self.commands)
        self.sim.step_on_device(1)
        if bool((self._status[:, 0] >= 0).any()):
            raise_on_blowup(self._status.cpu().numpy(), self.arms, self.dt, self.sim.blowup_distance,
                            self.sim.substeps)
        self.steps += live
        self._read(live)
        control = self.config.control
        on = self.distance < control.tolerance
        self.held = torch.where(live, torch.where(on, self.held + 1, 0), self.held)
        reward = -self.distance / control.reward_scale - (~on).double()
        terminated = self.task.succeeded(self.held)
        truncated = (self.steps >= self.episode_steps) & ~terminated
        return reward, terminated, truncated

    def displacements(self) -> torch.Tensor:
        """(arms, 1) the top's displacement along the drive now, m (`Arms.displacements`)."""
        h = self.host
        times = h.t0 + self.steps.cpu().numpy() * self.dt
        return torch.as_tensor(h.drives[0].displacement(times), device=self.device)[:, None]

    def frames(self) -> torch.Tensor:
        """(arms, H, W) uint8 camera frames of the arms now, drawn on the device (docs/model.md, Camera)."""
        if self._camera is None:
            from softarm.sim.raster import TensorRasteriser

            self._camera = TensorRasteriser(self.config.camera, self.body.outline, self.arms, self.device)
        return self._camera.render(self.x)

    def close(self) -> None:
        self.sim.close()

    def _read(self, mask: torch.Tensor) -> None:
        """The arms of the mask read their state, sensors and distance; every arm's target moves on."""
        x, v, activation = self._fresh
        self.sim.read_into(x, v, activation)
        self.x = torch.where(mask[:, None, None], x, self.x)
        self.v = torch.where(mask[:, None, None], v, self.v)
        self.activation = torch.where(mask[:, None], activation, self.activation)
        a, b = self.pair_ends[:, 0], self.pair_ends[:, 1]
        ideal = torch.linalg.vector_norm(self.x[:, a] - self.x[:, b], dim=-1) - self.pair_rest
        self.stretch = torch.where(mask[:, None], self.sensing.read(ideal, mask, self.steps, self.generator),
                                   self.stretch)
        share = self.task.progress(self.steps.double() * self.dt)
        self.target = self.ends[:, 0] + share[:, None] * (self.ends[:, 1] - self.ends[:, 0])
        distance = torch.linalg.vector_norm(self.x[:, self.tip].mean(dim=1) - self.target, dim=1)
        self.distance = torch.where(mask, distance, self.distance)


class DeviceSensing:
    """`softarm.envs.sensing.StepSensing` on tensors: bias from the episode's start (drawn on the host, from the
    arm's generator), drift and white noise from the device's generator, then quantisation and dropout."""

    def __init__(self, model: object, arms: int, sensors: int, frame_dt: float, device: torch.device):
        self.model, self.frame_dt = model, frame_dt
        self.bias = torch.zeros((arms, sensors), dtype=torch.float64, device=device)
        self.drift, self.last = torch.zeros_like(self.bias), torch.zeros_like(self.bias)

    def start(self, index: torch.Tensor, bias: torch.Tensor) -> None:
        self.bias[index] = bias
        self.drift[index] = 0.0

    def read(self, ideal: torch.Tensor, mask: torch.Tensor, steps: torch.Tensor,
             generator: torch.Generator) -> torch.Tensor:
        """(arms, P) readings from the ideal stretch (arms, P), m; the drift and dropout memory of the arms of the
        mask move on."""
        m = self.model
        out = ideal + self.bias
        if m.drift > 0:
            walk = torch.randn(out.shape, generator=generator, dtype=out.dtype, device=out.device)
            growing = (mask & (steps > 0))[:, None]  # the walk starts at the episode's first sample
            self.drift = torch.where(growing, self.drift + walk * (m.drift * self.frame_dt ** 0.5), self.drift)
            out = out + self.drift
        if m.noise > 0:
            out = out + m.noise * torch.randn(out.shape, generator=generator, dtype=out.dtype, device=out.device)
        if m.quantisation > 0:
            out = torch.round(out / m.quantisation) * m.quantisation
        if m.dropout_sensor >= 0:
            stuck = (steps > 0) & (steps.double() * self.frame_dt >= m.dropout_time)
            s = m.dropout_sensor
            out[:, s] = torch.where(stuck, self.last[:, s], out[:, s])
            self.last = torch.where(mask[:, None], out, self.last)
        return out
