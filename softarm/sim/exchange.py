"""Copies between a simulator's fields and kernel arrays, for a controller that reads and commands every step:
a kernel over preallocated arrays costs a fraction of a field's `to_numpy` / `from_numpy` (which allocate
and dispatch per call)."""

import taichi as ti

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
