"""The force step and the substep of one arm, as Taichi functions the simulator's kernel calls (docs/model.md,
Forces, Integration, Muscles)."""

import taichi as ti

from softarm.sim.drive_kernels import product_of_sines, sum_of_sines
from softarm.sim.muscle_fields import rest_scale
from softarm.sim.world import active_kinds, contact, node_load, spring_factor


@ti.func
def accumulate_forces(a: int, t: ti.f64, x: ti.template(), v: ti.template(), force: ti.template(),
                      inertia: ti.template(), springs: ti.template(), spring_params: ti.template(), mass: ti.template(),
                      free: ti.template(), gx: ti.f64, gy: ti.f64, world: ti.template(), disturbed: ti.template(),
                      muscles: ti.template(), muscled: ti.template()):
    """force[a] = gravity + every spring and damper (docs/model.md, Forces); spring_params[s] = (L0, k, b).
    With `disturbed` (a compile-time switch), also every disturbance active at run time t: payloads add to
    inertia[a] and the weight, pushes and contacts to the force, stiffness changes scale k. With `muscled`
    (likewise), each muscle's activation shortens its springs' rest lengths."""
    g = ti.Vector([gx, gy], ti.f64)
    bits = 0
    if ti.static(disturbed):
        bits = active_kinds(a, t, world.codes, world.windows)
    for i in range(x.shape[1]):
        if ti.static(disturbed):
            load = node_load(a, i, t, bits, world.codes, world.windows, world.params, world.nodes)
            inertia[a, i] = mass[i] + load[0]
            force[a, i] = inertia[a, i] * g + ti.Vector([load[1], load[2]], ti.f64)
            if free[i]:
                force[a, i] += contact(a, t, x[a, i], v[a, i], bits, world.codes, world.windows, world.params)
        else:
            force[a, i] = mass[i] * g
    for s in range(springs.shape[0]):
        ends, params = springs[s], spring_params[s]
        i, j = ends[0], ends[1]
        d = x[a, j] - x[a, i]
        length = ti.sqrt(d[0] * d[0] + d[1] * d[1])
        u = d * (1.0 / length)
        k = params[1]
        if ti.static(disturbed):
            k *= spring_factor(a, s, t, bits, world.codes, world.windows, world.params, world.springs)
        rest_length = params[0]
        if ti.static(muscled):
            rest_length *= rest_scale(a, s, muscles)
        magnitude = k * (length - rest_length) + params[2] * (v[a, j] - v[a, i]).dot(u)
        f = magnitude * u
        force[a, i] = force[a, i] + f
        force[a, j] = force[a, j] - f


@ti.func
def substep(a: int, t: ti.f64, h: ti.f64, kind: int, x: ti.template(), v: ti.template(), force: ti.template(),
            inertia: ti.template(), rest: ti.template(), mass: ti.template(), free: ti.template(),
            amplitude: ti.template(), freqs: ti.template(), amps: ti.template(), phases: ti.template(),
            direction: ti.template(), disturbed: ti.template()):
    drive = ti.Vector([0.0, 0.0], ti.f64)
    if kind == 0:
        drive = product_of_sines(t, amplitude[a], a, freqs)
    else:
        drive = sum_of_sines(t, a, freqs, amps, phases)
    e = direction[None]
    for i in range(x.shape[1]):
        if free[i]:
            if ti.static(disturbed):
                v[a, i] = v[a, i] + h * force[a, i] / inertia[a, i]
            else:
                v[a, i] = v[a, i] + h * force[a, i] / mass[i]
            x[a, i] = x[a, i] + h * v[a, i]
        else:
            for k in ti.static(range(2)):  # an axis the drive does not move stays exactly at rest (-0.0 too)
                x[a, i][k] = rest[i][k] + drive[0] * e[k] if e[k] != 0.0 else rest[i][k]
                v[a, i][k] = drive[1] * e[k] if e[k] != 0.0 else 0.0


@ti.func
def first_far_node(a: int, x: ti.template(), rest: ti.template(), free: ti.template(), limit: ti.f64) -> int:
    """Index of the first free node further than `limit` from rest (NaN counts as far), or -1."""
    found = -1
    for i in range(x.shape[1]):
        dx, dy = x[a, i][0] - rest[i][0], x[a, i][1] - rest[i][1]
        if free[i] and found < 0 and not (dx * dx + dy * dy <= limit * limit):
            found = i
    return found
