"""The arm at rest and at the edge of stability: hanging equilibrium, start state, largest stable step.

Everything here is float64 NumPy, computed once per run before any stepping (docs/model.md, Initial
state; Stability and blow-up).
"""

from typing import TYPE_CHECKING, Sequence

import numpy as np

from softarm.arm.body import Body
from softarm.arm.drive import Drive
from softarm.config import Config
from softarm.errors import ConfigError

if TYPE_CHECKING:
    from softarm.disturbances import Disturbance


def spring_forces(body: Body, positions: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """Net spring and damper force on every node (docs/model.md, Forces), float64; no gravity."""
    i, j = body.springs[:, 0], body.springs[:, 1]
    d = positions[j] - positions[i]
    length = np.linalg.norm(d, axis=1)
    u = d / length[:, None]
    rate = np.einsum("sk,sk->s", velocities[j] - velocities[i], u)
    f = (body.stiffness * (length - body.rest_lengths) + body.damping * rate)[:, None] * u
    out = np.zeros_like(positions)
    np.add.at(out, i, f)
    np.add.at(out, j, -f)
    return out


def hanging_equilibrium(body: Body, tolerance: float = 1e-11, max_iterations: int = 50) -> np.ndarray:
    """Positions where the springs hold the free nodes still against gravity, driven nodes at rest.

    The run starts here (at rest, f(0) = f'(0) = 0), so it shows the excitation's motion rather than
    the arm dropping from its unstretched layout. Newton's method on the free nodes, float64.
    """
    free = np.flatnonzero(body.free)
    x = body.rest.copy()
    zero = np.zeros_like(x)
    for _ in range(max_iterations):
        residual = spring_forces(body, x, zero) + body.masses[:, None] * body.gravity
        r = residual[free].ravel()
        if np.abs(r).max() < tolerance:
            return x
        step = np.linalg.solve(_stiffness_matrix(body, x)[np.ix_(_dofs(free), _dofs(free))], r)
        x[free] += step.reshape(-1, 2)
    raise ConfigError("the arm has no hanging equilibrium under gravity (Newton's method did not converge): "
                      "check body.node_mass, springs.stiffness and body.gravity")


def _dofs(nodes: np.ndarray) -> np.ndarray:
    return np.stack([2 * nodes, 2 * nodes + 1], 1).ravel()


def _stiffness_matrix(body: Body, x: np.ndarray) -> np.ndarray:
    """-dF/dx of the spring forces at positions x (2N x 2N), for Newton's method."""
    i, j = body.springs[:, 0], body.springs[:, 1]
    d = x[j] - x[i]
    length = np.linalg.norm(d, axis=1)
    u = d / length[:, None]
    uu = u[:, :, None] * u[:, None, :]
    blocks = body.stiffness[:, None, None] * (uu + (1 - body.rest_lengths / length)[:, None, None] * (np.eye(2) - uu))
    n = body.n_nodes
    K = np.zeros((n, 2, n, 2))
    for a, b_, sign in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
        np.add.at(K, (a, slice(None), b_), sign * blocks)
    return K.reshape(2 * n, 2 * n)


def max_stable_substep(body: Body, disturbances: Sequence["Disturbance"] = ()) -> float:
    """Largest symplectic-Euler step that is stable for every mode, by a Gershgorin bound.

    A mode x'' = -w^2 x - g x' stepped by semi-implicit Euler with step h is stable when
    h^2 w^2 + 2 g h < 4. Gershgorin bounds w^2 by max_i 2 sum(k)/m_i and g by max_i 2 sum(b)/m_i
    over the springs touching each free node; the bound is safe, not tight. With disturbances it holds
    for the stiffest moment: every stiffening at once (softening and payloads only make the step safer)
    and what every disturbance may add on every node (an obstacle's contact stiffness and damping, a drag's
    damping toward the water: `Disturbance.stability`, as a spring to a fixed point).
    """
    free = body.free
    stiffness = body.stiffness * np.prod([np.maximum(1.0, d.stiffness_factor(len(body.springs))) for d in disturbances]
                                         or [np.ones(len(body.springs))], axis=0)
    k_sum = np.zeros(body.n_nodes)
    b_sum = np.zeros(body.n_nodes)
    for col in (0, 1):
        np.add.at(k_sum, body.springs[:, col], stiffness)
        np.add.at(b_sum, body.springs[:, col], body.damping)
    holds = [d.stability() for d in disturbances]
    w2 = np.max((2 * k_sum[free] + sum(2 * k for k, _ in holds)) / body.masses[free])
    g = np.max((2 * b_sum[free] + sum(2 * b for _, b in holds)) / body.masses[free])
    return float((-2 * g + np.sqrt(4 * g * g + 16 * w2)) / (2 * w2))


def initial_state(hanging: np.ndarray, drive: Drive) -> tuple[np.ndarray, np.ndarray]:
    """Start state for a drive that is at (f(t0), f'(t0)) at t = 0.

    Gravity is uniform, so the hanging equilibrium shifted by f(t0) along the drive is still an
    equilibrium; giving every node the top's velocity f'(t0) makes the whole arm move with the drive
    at t = 0 instead of being jerked by it. For the paper's run (t0 = 0) this is the plain hanging arm.
    """
    positions = hanging + drive.along(float(drive.displacement(0.0)))
    velocities = np.zeros_like(hanging)
    velocities[:] = drive.along(float(drive.velocity(0.0)))
    return positions, velocities


def check_step(config: Config, body: Body, disturbances: Sequence["Disturbance"] = ()) -> None:
    """Refuse a substep above the stability limit of semi-implicit Euler (with every disturbance of the run),
    naming the substeps that work."""
    h_max = max_stable_substep(body, disturbances)
    dt = config.integration.frame_dt
    substeps = config.integration.substeps
    if dt / substeps > h_max:
        needed = int(np.ceil(dt / h_max))
        raise ConfigError(
            f"config key 'integration.substeps' = {substeps} is unstable: a step of {1e3 * dt / substeps:.3g} ms "
            f"exceeds the stability limit {1e3 * h_max:.3g} ms of these springs, masses and disturbances; "
            f"use integration.substeps >= {needed} (or --substeps {needed})")
