"""The arm as plain arrays: rest layout, springs, driven nodes, sensors and outline (docs/model.md, Body).

Everything downstream (the Taichi simulator, the NumPy reference, the recorder) reads a `Body`, so
the geometry is built once, here, from the config.
"""

from dataclasses import dataclass, field

import numpy as np

from softarm.config import Config
from softarm.errors import ConfigError
from softarm.sensors import KINDS


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
    # the other sensor kinds' placements, by kind (softarm.sensors), for those [sensors] declares
    placed: dict[str, np.ndarray] = field(default_factory=dict)

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
        raise ConfigError(f"config key 'body.driven' = {driven.tolist()} must name at least one node "
                          f"and leave one free")
    if len(outline) < 3:
        raise ConfigError(f"config key 'camera.outline' = {outline.tolist()} needs at least 3 nodes")

    placed = {name: kind().check(getattr(config.sensors, name), n, f"sensors.{name}")
              for name, kind in KINDS.items() if getattr(config.sensors, name)}
    s = len(springs)
    return Body(rest=rest, masses=np.full(n, b.node_mass), springs=springs, rest_lengths=rest_lengths,
                stiffness=np.full(s, config.springs.stiffness), damping=np.full(s, config.springs.damping),
                driven=driven, sensors=sensors, outline=outline, gravity=np.array(b.gravity, float), placed=placed)


def default_outline(node: np.ndarray) -> np.ndarray:
    """Down the left edge, across the tip, up the right edge, back across the top."""
    return np.concatenate([node[:, 0], node[-1, 1:], node[-2::-1, -1], node[0, -2:0:-1]])


def _check_nodes(indices: np.ndarray, n: int, key: str) -> None:
    bad = [int(i) for i in np.ravel(indices) if not 0 <= i < n]
    if bad:
        raise ConfigError(f"config key '{key}' = {np.ravel(indices).tolist()} names node {bad[0]}, "
                          f"but the body has nodes 0..{n - 1}")
