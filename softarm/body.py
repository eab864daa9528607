"""The arm as plain arrays: rest layout, springs, driven nodes, sensors and outline (MODEL.md, Body).

Everything downstream (the Taichi simulator, the NumPy reference, the recorder) reads a `Body`, so
the geometry is built once, here, from the config.
"""

from dataclasses import dataclass

import numpy as np

from softarm.config import Config
from softarm.errors import ConfigError


@dataclass(frozen=True)
class Body:
    rest: np.ndarray          # (N, 2) rest positions, m
    masses: np.ndarray        # (N,) kg
    springs: np.ndarray       # (S, 2) node index pairs
    rest_lengths: np.ndarray  # (S,) m
    stiffness: np.ndarray     # (S,) N/m
    damping: np.ndarray       # (S,) N s/m
    driven: np.ndarray        # (D,) node indices moved by the excitation
    sensors: np.ndarray       # (P, 2) node index pairs
    outline: np.ndarray       # (V,) node indices of the closed outline polygon
    gravity: np.ndarray       # (2,) m/s^2

    @property
    def n_nodes(self) -> int:
        return len(self.rest)

    @property
    def free(self) -> np.ndarray:
        """Boolean mask of the nodes that the forces move (all but the driven ones)."""
        mask = np.ones(self.n_nodes, bool)
        mask[self.driven] = False
        return mask


def build_body(config: Config) -> Body:
    """The tapered grid arm of the config, hanging from its top row, with node indices checked."""
    b = config.body
    rows, cols = b.rows, b.columns
    node = np.arange(rows * cols).reshape(rows, cols)
    frac = np.arange(rows) / (rows - 1)
    widths = b.base_width + (b.tip_width - b.base_width) * frac
    x = widths[:, None] * (np.arange(cols)[None, :] / (cols - 1) - 0.5)
    y = np.repeat(-b.length * frac[:, None], cols, axis=1)
    rest = np.stack([x.ravel(), y.ravel()], axis=1)

    pairs = [np.stack([node[:, :-1].ravel(), node[:, 1:].ravel()], 1),       # horizontal
             np.stack([node[:-1, :].ravel(), node[1:, :].ravel()], 1),       # vertical
             np.stack([node[:-1, :-1].ravel(), node[1:, 1:].ravel()], 1),    # diagonal \
             np.stack([node[:-1, 1:].ravel(), node[1:, :-1].ravel()], 1)]    # diagonal /
    springs = np.concatenate(pairs)
    rest_lengths = np.linalg.norm(rest[springs[:, 1]] - rest[springs[:, 0]], axis=1)

    n = rows * cols
    driven = np.array(b.driven if b.driven is not None else node[0], int)
    outline = np.array(config.camera.outline if config.camera.outline is not None else default_outline(node), int)
    sensors = np.array(config.sensors.pairs, int).reshape(-1, 2)
    _check_nodes(driven, n, "body.driven")
    _check_nodes(outline, n, "camera.outline")
    for k, pair in enumerate(sensors):
        _check_nodes(pair, n, f"sensors.pairs[{k}]")
    if len(driven) == 0 or len(np.unique(driven)) == n:
        raise ConfigError(f"config key 'body.driven' = {driven.tolist()} must name at least one node and leave one free")
    if len(outline) < 3:
        raise ConfigError(f"config key 'camera.outline' = {outline.tolist()} needs at least 3 nodes")

    s = len(springs)
    return Body(rest=rest, masses=np.full(n, b.node_mass), springs=springs, rest_lengths=rest_lengths,
                stiffness=np.full(s, config.springs.stiffness), damping=np.full(s, config.springs.damping),
                driven=driven, sensors=sensors, outline=outline, gravity=np.array(b.gravity, float))


def default_outline(node: np.ndarray) -> np.ndarray:
    """Down the left edge, across the tip, up the right edge, back across the top."""
    return np.concatenate([node[:, 0], node[-1, 1:], node[-2::-1, -1], node[0, -2:0:-1]])


def _check_nodes(indices: np.ndarray, n: int, key: str) -> None:
    bad = [int(i) for i in np.ravel(indices) if not 0 <= i < n]
    if bad:
        raise ConfigError(f"config key '{key}' = {np.ravel(indices).tolist()} names node {bad[0]}, "
                          f"but the body has nodes 0..{n - 1}")


def spring_forces(body: Body, positions: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """Net spring and damper force on every node (MODEL.md, Forces), float64; no gravity."""
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
    n = body.n_nodes
    K = np.zeros((2 * n, 2 * n))
    for (i, j), k, l0 in zip(body.springs, body.stiffness, body.rest_lengths):
        d = x[j] - x[i]
        length = np.linalg.norm(d)
        u = d / length
        block = k * (np.outer(u, u) + (1 - l0 / length) * (np.eye(2) - np.outer(u, u)))
        for a, b_, sign in ((i, i, 1), (j, j, 1), (i, j, -1), (j, i, -1)):
            K[2 * a:2 * a + 2, 2 * b_:2 * b_ + 2] += sign * block
    return K


def max_stable_substep(body: Body) -> float:
    """Largest symplectic-Euler step that is stable for every mode, by a Gershgorin bound.

    A mode x'' = -w^2 x - g x' stepped by semi-implicit Euler with step h is stable when
    h^2 w^2 + 2 g h < 4. Gershgorin bounds w^2 by max_i 2 sum(k)/m_i and g by max_i 2 sum(b)/m_i
    over the springs touching each free node; the bound is safe, not tight.
    """
    free = body.free
    k_sum = np.zeros(body.n_nodes)
    b_sum = np.zeros(body.n_nodes)
    for col in (0, 1):
        np.add.at(k_sum, body.springs[:, col], body.stiffness)
        np.add.at(b_sum, body.springs[:, col], body.damping)
    w2 = np.max(2 * k_sum[free] / body.masses[free])
    g = np.max(2 * b_sum[free] / body.masses[free])
    return float((-2 * g + np.sqrt(4 * g * g + 16 * w2)) / (2 * w2))


def initial_state(hanging: np.ndarray, displacement: float, velocity: float) -> tuple[np.ndarray, np.ndarray]:
    """Start state for a drive that is at (f(t0), f'(t0)) at t = 0.

    Gravity is vertical, so the hanging equilibrium shifted sideways by f(t0) is still an
    equilibrium; giving every node the top's velocity f'(t0) makes the whole arm move with the drive
    at t = 0 instead of being jerked by it. For the paper's run (t0 = 0) this is the plain hanging arm.
    """
    positions = hanging + np.array([displacement, 0.0])
    velocities = np.zeros_like(hanging)
    velocities[:, 0] = velocity
    return positions, velocities
