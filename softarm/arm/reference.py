"""A plain float64 NumPy implementation of docs/model.md, independent of the Taichi simulator.

It exists to check `softarm.sim.physics` (tests) and to give the benchmark a baseline: the forces are
written out again here from the equations of docs/model.md, not taken from `statics.py`, so a slip in one
implementation shows up as a disagreement with the other. One arm, readable over fast.
"""

from typing import TYPE_CHECKING, Optional, Sequence

import numpy as np

from softarm.arm.body import Body
from softarm.arm.drive import Drive
from softarm.arm.muscles import Muscles

if TYPE_CHECKING:
    from softarm.disturbances import Disturbance


def simulate_reference(body: Body, drive: Drive, positions: np.ndarray, velocities: np.ndarray,
                       frame_dt: float, substeps: int, n_frames: int,
                       disturbances: Sequence["Disturbance"] = (), muscles: Optional[Muscles] = None,
                       commands: Optional[np.ndarray] = None) -> np.ndarray:
    """(n_frames, N, 2) positions at t_k = k * frame_dt, k = 0..n_frames-1; frame 0 is the given state.

    Semi-implicit (symplectic) Euler with `substeps` steps per frame: forces at the current state (and the
    disturbances active at the step's run time), then v += h F / m on the free nodes (m with the active
    payloads), then x += h v with the new v; after each step the driven nodes are put at rest + f(t) e with
    velocity f'(t) e (e: the drive's direction). With `muscles`, commands[k] (G,) is held from frame k to k + 1;
    each step first relaxes the activations (from 0) toward it, then shortens the muscles' rest lengths.
    """
    x = np.array(positions, dtype=np.float64)
    v = np.array(velocities, dtype=np.float64)
    i, j = body.springs[:, 0], body.springs[:, 1]
    free = np.ones(len(x), bool)
    free[body.driven] = False
    h = frame_dt / substeps
    activation = np.zeros(muscles.count if muscles is not None else 0)
    rest_lengths = body.rest_lengths

    out = np.empty((n_frames,) + x.shape)
    for k in range(n_frames):
        out[k] = x
        if k == n_frames - 1:
            break
        for s in range(substeps):
            now = ((k * substeps + s) / substeps) * frame_dt
            active = [d for d in disturbances if d.active(now)]
            mass = body.masses + sum((d.extra_mass(len(x)) for d in active), np.zeros(len(x)))
            stiffness = body.stiffness * np.prod([d.stiffness_factor(len(i)) for d in active] or [np.ones(len(i))],
                                                 axis=0)
            if muscles is not None:
                activation = muscles.relax(activation, np.asarray(commands[k], np.float64), h)
                rest_lengths = muscles.rest_lengths(body, activation)
            force = (_spring_damper_forces(x, v, i, j, rest_lengths, stiffness, body.damping)
                     + mass[:, None] * body.gravity[None, :])
            for d in active:
                force += d.forces(x, v) * free[:, None]
            v[free] += h * force[free] / mass[free][:, None]
            x[free] += h * v[free]
            t_next = ((k * substeps + s + 1) / substeps) * frame_dt
            x[body.driven] = body.rest[body.driven] + drive.along(float(drive.displacement(t_next)))
            v[body.driven] = drive.along(float(drive.velocity(t_next)))
    return out


def _spring_damper_forces(x: np.ndarray, v: np.ndarray, i: np.ndarray, j: np.ndarray, rest_length: np.ndarray,
                          stiffness: np.ndarray, damping: np.ndarray) -> np.ndarray:
    """Per spring (i, j): f = (k (L - L0) + b (v_j - v_i) . u) u pulls i towards j; j gets -f."""
    d = x[j] - x[i]
    length = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2)
    u = d / length[:, None]
    stretch_rate = ((v[j] - v[i]) * u).sum(axis=1)
    f = (stiffness * (length - rest_length) + damping * stretch_rate)[:, None] * u
    n = len(x)
    force = np.empty_like(x)
    for axis in (0, 1):
        force[:, axis] = (np.bincount(i, weights=f[:, axis], minlength=n)
                          - np.bincount(j, weights=f[:, axis], minlength=n))
    return force
