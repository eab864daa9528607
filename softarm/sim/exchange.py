"""Copies between a simulator's fields and kernel arrays, for a controller that reads and commands every step:
a kernel over preallocated arrays costs a fraction of a field's `to_numpy` / `from_numpy` (which allocate
and dispatch per call). `Exchange` is the part of `Simulator` that a controller calls: through NumPy arrays, or
through torch tensors on the device for a controller whose state never leaves it."""

from typing import Optional

import numpy as np
import taichi as ti

from softarm.sim.muscle_fields import MuscleFields
from softarm.sim.runtime import host, upload

f64nd2 = ti.types.ndarray(dtype=ti.f64, ndim=2)
f64nd3 = ti.types.ndarray(dtype=ti.f64, ndim=3)


@ti.kernel
def read_states(x: ti.template(), v: ti.template(), out_x: f64nd3, out_v: f64nd3):
    """out_x[a, i, :] = x[a, i] and out_v[a, i, :] = v[a, i], in one launch."""
    for a, i in x:
        for k in ti.static(range(2)):
            out_x[a, i, k] = x[a, i][k]
            out_v[a, i, k] = v[a, i][k]


@ti.kernel
def read_scalars(field: ti.template(), out: f64nd2):
    for a, g in field:
        out[a, g] = field[a, g]


@ti.kernel
def write_scalars(field: ti.template(), values: f64nd2):
    for a, g in field:
        field[a, g] = values[a, g]



i32nd1 = ti.types.ndarray(dtype=ti.i32, ndim=1)


@ti.kernel
def place_states(x: ti.template(), v: ti.template(), activation: ti.template(), arms: i32nd1, new_x: f64nd3,
                 new_v: f64nd3):
    """Arm arms[k] gets the state (new_x[k], new_v[k]) and relaxed muscles; the other arms keep theirs."""
    for k, i in ti.ndrange(arms.shape[0], x.shape[1]):
        x[arms[k], i] = ti.Vector([new_x[k, i, 0], new_x[k, i, 1]])
        v[arms[k], i] = ti.Vector([new_v[k, i, 0], new_v[k, i, 1]])
    for k, g in ti.ndrange(arms.shape[0], activation.shape[1]):
        activation[arms[k], g] = 0.0


class Exchange:
    """A simulator's state as a controller reads, commands and resets it (mixed into `Simulator`, whose fields,
    muscles and `launch` it uses)."""

    def command(self, commands: np.ndarray) -> None:
        """Hold each arm's muscle commands (arms, G), in [0, 1], from the next substep on."""
        write_scalars(self._require_muscles().command, upload(np.asarray(commands, np.float64)))

    def activation(self) -> np.ndarray:
        """(arms, G) activations now."""
        read_scalars(self._require_muscles().activation, self._activation)
        return host(self._activation).copy()

    def state(self) -> tuple[np.ndarray, np.ndarray]:
        """(arms, N, 2) positions and velocities now (after the last step), float64 copies."""
        read_states(self.x, self.v, *self._state)
        return host(self._state[0]).copy(), host(self._state[1]).copy()

    def place(self, arms: np.ndarray, positions: np.ndarray, velocities: np.ndarray,
              activation: Optional[np.ndarray] = None) -> None:
        """Put the given arms (indices) at new states, e.g. an environment's reset; the others keep theirs."""
        x, v = self.state()
        x[arms], v[arms] = positions, velocities
        self.x.from_numpy(x)
        self.v.from_numpy(v)
        if activation is not None:
            now = self.activation()
            now[arms] = activation
            self.actuators.activation.from_numpy(now)

    def keep_on_device(self, positions: object, status: object) -> None:
        """Have the kernel write the block's positions (arms, block_frames, N, 2) float64 and the blow-up status
        (arms, 2) int32, -1 filled, into the caller's arrays: torch tensors on the simulator's device, for a
        controller whose state never leaves it (`step_on_device`)."""
        self._positions, self._status = positions, status

    def step_on_device(self, n_frames: int = 1) -> None:
        """Step n_frames with nothing copied to the host: `history` is not filled, and the caller reads the state
        through `read_into` and the blow-ups from its status array (`keep_on_device`)."""
        self.launch(n_frames)
        self.frame += n_frames

    def read_into(self, x: object, v: object, activation: object) -> None:
        """The state now into the caller's arrays, (arms, N, 2), (arms, N, 2) and (arms, G) float64: on a GPU, torch
        tensors on it (one copy within the device)."""
        read_states(self.x, self.v, x, v)
        read_scalars(self._require_muscles().activation, activation)

    def command_from(self, commands: object) -> None:
        """`command` from an array already on the device: (arms, G) float64, contiguous."""
        write_scalars(self._require_muscles().command, commands)

    def place_on_device(self, arms: object, positions: object, velocities: object) -> None:
        """`place` for the arms of an index array (k,) int32, states (k, N, 2) float64, all on the device, muscles
        relaxed; no state passes through the host."""
        place_states(self.x, self.v, self._require_muscles().activation, arms, positions, velocities)

    def _require_muscles(self) -> MuscleFields:
        if self.actuators is None:
            raise ValueError("this simulator has no muscles: build it with a Muscles that has groups")
        return self.actuators
