"""Where the tip can be: its resting places under random muscle commands, the targets the tasks draw from.

Each place is a static equilibrium (Newton's method on the springs with the commanded rest lengths, gravity
included), so every target is reachable and holdable by a constant command. The set depends only on the config
(its own seeded draw), so every env and seed of one config shares it; it is computed once per process.
"""

import dataclasses
import functools

import numpy as np

from softarm.arm.body import Body, build_body
from softarm.arm.muscles import Muscles, build_muscles
from softarm.arm.statics import hanging_equilibrium
from softarm.config import Config

STREAM = 20_261_202  # the workspace draw's own random stream


def tip_nodes(body: Body, columns: int) -> np.ndarray:
    """The tip row's nodes: the tip is their mean (the middle node of an odd row)."""
    return np.arange(body.n_nodes - columns, body.n_nodes)


@functools.lru_cache(maxsize=8)
def reachable(config: Config) -> np.ndarray:
    """(control.workspace_samples, 2) resting tip positions, m, under commands drawn uniformly from [0, 1]^G."""
    body = build_body(config)
    muscles = build_muscles(config, body)
    commands = np.random.default_rng(STREAM).uniform(0.0, 1.0, (config.control.workspace_samples, muscles.count))
    tip = tip_nodes(body, config.body.columns)
    return np.stack([resting(body, muscles, u)[tip].mean(axis=0) for u in commands])


def resting(body: Body, muscles: Muscles, command: np.ndarray) -> np.ndarray:
    """(N, 2) node positions at rest under a constant command (its activations equal it once settled)."""
    return hanging_equilibrium(dataclasses.replace(body, rest_lengths=muscles.rest_lengths(body, command)))
