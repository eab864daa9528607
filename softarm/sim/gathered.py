"""The substep as a GPU runs it: one thread per arm, the arms innermost in memory, and every node's force gathered
from its own springs instead of scattered from each spring to its two ends.

On a GPU, neighbouring threads are neighbouring arms, so with the arms innermost (`[node][arm]`) a warp's 32 loads of
node i are one contiguous run of memory. Scattering a spring's force to both ends read and wrote a force array twice
per spring; gathering reads the positions and velocities of the node's neighbours and writes the node's new state
once, into the second of two buffers (the forces of a substep are those of its start, so no node may be moved
before every node's force is known). Each node starts from its weight and load, adds its contact, then its
springs' forces in the springs' order, `+f` where it is a spring's first end and `-f` where it is the second: the
same operations, in the same order, as `forces.accumulate_forces`, so the two kernels compute the same numbers
(tests/sim/test_gathered.py holds them together). Each spring's force is computed at both of its ends, twice the
arithmetic for half the memory traffic, the trade a GPU wants.
"""

import numpy as np
import taichi as ti

from softarm.disturbances.slots import active_kinds, free_node_force, node_load, spring_factor
from softarm.sim.forces import drive_at, first_far_node
from softarm.sim.muscle_fields import relax, rest_scale


def incident_springs(springs: np.ndarray, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR of every node's springs in the springs' order: (starts (N + 1,), entries (2 S,)); an entry is s + 1 where
    the node is spring s's first end (its force adds) and -(s + 1) where it is the second (its force subtracts)."""
    ends = [[] for _ in range(nodes)]
    for s, (i, j) in enumerate(np.asarray(springs)):
        ends[i].append(s + 1)
        ends[j].append(-(s + 1))
    starts = np.cumsum([0] + [len(e) for e in ends]).astype(np.int32)
    return starts, np.array([s for e in ends for s in e], np.int32)


@ti.func
def spring_force(a: int, s: int, t: ti.f64, bits: int, x: ti.template(), v: ti.template(), sim: ti.template(),
                 disturbed: ti.template(), muscled: ti.template()) -> ti.math.vec2:
    """The force of spring s on its first end (its second feels the opposite), from the state in x, v."""
    ends, params = sim.springs[s], sim.spring_params[s]
    i, j = ends[0], ends[1]
    d = x[a, j] - x[a, i]
    length = ti.sqrt(d[0] * d[0] + d[1] * d[1])
    u = d * (1.0 / length)
    k = params[1]
    if ti.static(disturbed):
        k *= spring_factor(a, s, t, bits, sim.world)
    rest_length = params[0]
    if ti.static(muscled):
        rest_length *= rest_scale(a, s, sim.actuators)
    magnitude = k * (length - rest_length) + params[2] * (v[a, j] - v[a, i]).dot(u)
    return magnitude * u


@ti.func
def gathered_substep(a: int, step: int, substeps: int, frame_dt: ti.f64, h: ti.f64, gx: ti.f64, gy: ti.f64, kind: int,
                     decay: ti.f64, x: ti.template(), v: ti.template(), x_next: ti.template(), v_next: ti.template(),
                     sim: ti.template(), disturbed: ti.template(), muscled: ti.template()):
    """Substep number `step` of the run for arm a: forces at its start from (x, v), the new state into
    (x_next, v_next); the driven nodes set to the drive at its end."""
    now = ti.cast(step, ti.f64) / substeps * frame_dt
    t = ti.cast(step + 1, ti.f64) / substeps * frame_dt
    if ti.static(muscled):
        relax(a, decay, sim.actuators)
    bits = 0
    if ti.static(disturbed):
        bits = active_kinds(a, now, sim.world)
    drive = drive_at(a, t + sim.time_offset[a], kind, sim.amplitude, sim.freqs, sim.amps, sim.phases)
    e = sim.direction[None]
    g = ti.Vector([gx, gy], ti.f64)
    for i in range(x.shape[1]):
        if sim.free[i]:
            inertia = sim.mass[i]
            f = inertia * g
            if ti.static(disturbed):
                load = node_load(a, i, now, bits, sim.world)
                inertia = sim.mass[i] + load[0]
                f = inertia * g + ti.Vector([load[1], load[2]], ti.f64)
                f += free_node_force(a, now, x[a, i], v[a, i], bits, sim.world)
            for k in range(sim.incident_start[i], sim.incident_start[i + 1]):
                entry = sim.incident[k]
                if entry > 0:
                    f = f + spring_force(a, entry - 1, now, bits, x, v, sim, disturbed, muscled)
                else:
                    f = f - spring_force(a, -entry - 1, now, bits, x, v, sim, disturbed, muscled)
            v_new = v[a, i] + h * f / inertia
            v_next[a, i] = v_new
            x_next[a, i] = x[a, i] + h * v_new
        else:
            for c in ti.static(range(2)):  # an axis the drive does not move stays exactly at rest (-0.0 too)
                x_next[a, i][c] = sim.rest[i][c] + drive[0] * e[c] if e[c] != 0.0 else sim.rest[i][c]
                v_next[a, i][c] = drive[1] * e[c] if e[c] != 0.0 else 0.0


f64nd = ti.types.ndarray(dtype=ti.f64, ndim=4)
i32nd = ti.types.ndarray(dtype=ti.i32, ndim=2)


@ti.kernel
def advance_gathered(sim: ti.template(), positions: f64nd, status: i32nd, first_frame: ti.i32, n_frames: ti.i32,
                     substeps: ti.i32, frame_dt: ti.f64, blowup_distance: ti.f64, gx: ti.f64, gy: ti.f64, kind: ti.i32,
                     decay: ti.f64, disturbed: ti.template(), muscled: ti.template()):
    """`Simulator._advance` for the gathered layout: arm a's thread records frames first_frame.. into
    positions[a, :n_frames] and steps between them, its state moving between the buffers (x, v) and (x2, v2)
    substep by substep and back into (x, v) at the end, where the simulator keeps it between blocks."""
    h = frame_dt / substeps
    for a in range(sim.x.shape[0]):
        current = 0  # the buffer arm a's state is in
        for f in range(n_frames):
            if current == 0:
                record(a, f, sim.x, positions)
            else:
                record(a, f, sim.x2, positions)
            if status[a, 0] < 0:
                k = first_frame + f
                for s in range(substeps):
                    step = k * substeps + s
                    if current == 0:
                        gathered_substep(a, step, substeps, frame_dt, h, gx, gy, kind, decay, sim.x, sim.v, sim.x2,
                                         sim.v2, sim, disturbed, muscled)
                    else:
                        gathered_substep(a, step, substeps, frame_dt, h, gx, gy, kind, decay, sim.x2, sim.v2, sim.x,
                                         sim.v, sim, disturbed, muscled)
                    current = 1 - current
                far = -1
                if current == 0:
                    far = first_far_node(a, sim.x, sim.rest, sim.free, blowup_distance)
                else:
                    far = first_far_node(a, sim.x2, sim.rest, sim.free, blowup_distance)
                if far >= 0:
                    status[a, 0] = k + 1
                    status[a, 1] = far
        if current == 1:
            for i in range(sim.x.shape[1]):
                sim.x[a, i] = sim.x2[a, i]
                sim.v[a, i] = sim.v2[a, i]


@ti.func
def record(a: int, f: int, x: ti.template(), positions: ti.template()):
    for i in range(x.shape[1]):
        positions[a, f, i, 0] = x[a, i][0]
        positions[a, f, i, 1] = x[a, i][1]
