"""The force step and the substep of a group of arms, as Taichi functions the simulator's kernel calls
(docs/model.md, Forces, Integration, Muscles).

A group is `lanes` arms base, base + 1, ... stepped together: every loop over nodes or springs does the same
scalar work for each arm of the group in turn (a compile-time loop over the lanes), on fields that keep the
group's arms next to each other, so the compiler turns the lanes into vector instructions. Each arm's
arithmetic is exactly that of an arm stepped alone.
"""

import taichi as ti

from softarm.disturbances.slots import active_kinds, free_node_force, node_load, spring_factor
from softarm.sim.drive_kernels import product_of_sines, sum_of_sines
from softarm.sim.muscle_fields import rest_scale


@ti.func
def accumulate_forces(base: int, lanes: ti.template(), t: ti.f64, x: ti.template(), v: ti.template(),
                      force: ti.template(), inertia: ti.template(), springs: ti.template(),
                      spring_params: ti.template(), mass: ti.template(), free: ti.template(), gx: ti.f64, gy: ti.f64,
                      world: ti.template(), disturbed: ti.template(), muscles: ti.template(), muscled: ti.template()):
    """force[a] = gravity + every spring and damper (docs/model.md, Forces) for the group's arms a;
    spring_params[s] = (L0, k, b). With `disturbed` (a compile-time switch), also every disturbance active at run
    time t: loads add to inertia[a], the weight and the force, forces on free nodes (contact, drag) to the force,
    stiffness changes scale k.
    With `muscled` (likewise), each muscle's activation shortens its springs' rest lengths."""
    g = ti.Vector([gx, gy], ti.f64)
    bits = ti.Vector([0] * lanes, ti.i32)
    if ti.static(disturbed):
        for w in ti.static(range(lanes)):
            bits[w] = active_kinds(base + w, t, world)
    for i in range(x.shape[1]):
        for w in ti.static(range(lanes)):
            a = base + w
            if ti.static(disturbed):
                load = node_load(a, i, t, bits[w], world)
                inertia[a, i] = mass[i] + load[0]
                force[a, i] = inertia[a, i] * g + ti.Vector([load[1], load[2]], ti.f64)
                if free[i]:
                    force[a, i] += free_node_force(a, t, x[a, i], v[a, i], bits[w], world)
            else:
                force[a, i] = mass[i] * g
    for s in range(springs.shape[0]):
        ends, params = springs[s], spring_params[s]
        i, j = ends[0], ends[1]
        for w in ti.static(range(lanes)):
            a = base + w
            d = x[a, j] - x[a, i]
            length = ti.sqrt(d[0] * d[0] + d[1] * d[1])
            u = d * (1.0 / length)
            k = params[1]
            if ti.static(disturbed):
                k *= spring_factor(a, s, t, bits[w], world)
            rest_length = params[0]
            if ti.static(muscled):
                rest_length *= rest_scale(a, s, muscles)
            magnitude = k * (length - rest_length) + params[2] * (v[a, j] - v[a, i]).dot(u)
            f = magnitude * u
            force[a, i] = force[a, i] + f
            force[a, j] = force[a, j] - f


@ti.func
def drive_at(a: int, t: ti.f64, kind: int, amplitude: ti.template(), freqs: ti.template(), amps: ti.template(),
             phases: ti.template()) -> ti.math.vec2:
    """(f(t), f'(t)) of arm a's excitation (docs/model.md, Excitation)."""
    drive = ti.Vector([0.0, 0.0], ti.f64)
    if kind == 0:
        drive = product_of_sines(t, amplitude[a], a, freqs)
    else:
        drive = sum_of_sines(t, a, freqs, amps, phases)
    return drive


@ti.func
def substep(base: int, lanes: ti.template(), t: ti.f64, h: ti.f64, kind: int, x: ti.template(), v: ti.template(),
            force: ti.template(), inertia: ti.template(), rest: ti.template(), mass: ti.template(),
            free: ti.template(), amplitude: ti.template(), time_offset: ti.template(), freqs: ti.template(),
            amps: ti.template(), phases: ti.template(), direction: ti.template(), disturbed: ti.template()):
    """Semi-implicit Euler for the group's free nodes; the driven nodes set to the drive at the end of the
    substep, run time t (arm a's excitation time: t + time_offset[a])."""
    value, rate = ti.Vector([0.0] * lanes, ti.f64), ti.Vector([0.0] * lanes, ti.f64)
    for w in ti.static(range(lanes)):
        drive = drive_at(base + w, t + time_offset[base + w], kind, amplitude, freqs, amps, phases)
        value[w], rate[w] = drive[0], drive[1]
    e = direction[None]
    for i in range(x.shape[1]):
        for w in ti.static(range(lanes)):
            a = base + w
            if free[i]:
                if ti.static(disturbed):
                    v[a, i] = v[a, i] + h * force[a, i] / inertia[a, i]
                else:
                    v[a, i] = v[a, i] + h * force[a, i] / mass[i]
                x[a, i] = x[a, i] + h * v[a, i]
            else:
                for k in ti.static(range(2)):  # an axis the drive does not move stays exactly at rest (-0.0 too)
                    x[a, i][k] = rest[i][k] + value[w] * e[k] if e[k] != 0.0 else rest[i][k]
                    v[a, i][k] = rate[w] * e[k] if e[k] != 0.0 else 0.0


@ti.func
def first_far_node(a: int, x: ti.template(), rest: ti.template(), free: ti.template(), limit: ti.f64) -> int:
    """Index of the first free node further than `limit` from rest (NaN counts as far), or -1."""
    found = -1
    for i in range(x.shape[1]):
        dx, dy = x[a, i][0] - rest[i][0], x[a, i][1] - rest[i][1]
        if free[i] and found < 0 and not (dx * dx + dy * dy <= limit * limit):
            found = i
    return found
