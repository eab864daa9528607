"""A new simulator's fields filled in one kernel launch.

Taichi builds every kernel from Python's syntax tree before it asks its offline cache, and `from_numpy`
is one kernel per field: with thirteen of them a 64-arm simulator took 0.26 s to make, with this one 0.10 s.
"""

import taichi as ti

f64nd1, f64nd2, f64nd3 = (ti.types.ndarray(dtype=ti.f64, ndim=n) for n in (1, 2, 3))
i32nd1, i32nd2 = (ti.types.ndarray(dtype=ti.i32, ndim=n) for n in (1, 2))


@ti.kernel
def load(sim: ti.template(), x: f64nd3, v: f64nd3, rest: f64nd2, mass: f64nd1, free: i32nd1, springs: i32nd2,
         params: f64nd2, per_arm: f64nd2, drive: f64nd3, direction: f64nd1):
    """States (arms, N, 2); the body (rest (N, 2), mass, free, springs (S, 2), params (S, 3): rest length,
    stiffness, damping); per arm (amplitude, time offset); the drive's (frequencies, amplitudes, phases)
    (3, arms, K); the drive's direction (2,)."""
    for a, i in sim.x:
        sim.x[a, i] = ti.Vector([x[a, i, 0], x[a, i, 1]])
        sim.v[a, i] = ti.Vector([v[a, i, 0], v[a, i, 1]])
    for i in sim.rest:
        sim.rest[i] = ti.Vector([rest[i, 0], rest[i, 1]])
        sim.mass[i] = mass[i]
        sim.free[i] = free[i]
    for e in sim.springs:
        sim.springs[e] = ti.Vector([springs[e, 0], springs[e, 1]])
        sim.spring_params[e] = ti.Vector([params[e, 0], params[e, 1], params[e, 2]])
    for a in sim.amplitude:
        sim.amplitude[a] = per_arm[a, 0]
        sim.time_offset[a] = per_arm[a, 1]
    for a, k in sim.freqs:
        sim.freqs[a, k] = drive[0, a, k]
        sim.amps[a, k] = drive[1, a, k]
        sim.phases[a, k] = drive[2, a, k]
    sim.direction[None] = ti.Vector([direction[0], direction[1]])
