"""Muscles: the Taichi kernel against the NumPy reference, the activation dynamics against its closed form, and a
static closed form (rest lengths that imply an arc bend the arm onto that arc)."""

import math

import numpy as np
import pytest

from softarm.arm.muscles import build_muscles
from softarm.arm.reference import simulate_reference
from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator

STILL_TOP = {"excitation.amplitude": 0.0}


def muscled(config, arms=1):
    batch = arm_batch(config, seeds=range(arms))
    muscles = build_muscles(config, batch.body)
    return batch, muscles, Simulator.from_config(config, batch, muscles=muscles)


@pytest.mark.slow
def test_commanded_muscles_match_the_numpy_reference_frame_by_frame():
    config = load_config(overrides=STILL_TOP)
    batch, muscles, sim = muscled(config)
    commands = np.random.default_rng(3).uniform(0, 1, (60, muscles.count)).repeat(5, axis=0)  # new every 50 ms
    got = np.stack([step(sim, u) for u in commands[:-1]])
    expected = simulate_reference(batch.body, batch.drives[0], batch.positions[0], batch.velocities[0],
                                  config.integration.frame_dt, config.integration.substeps, len(commands),
                                  muscles=muscles, commands=commands)
    assert np.abs(expected[-1] - expected[0]).max() > 5e-3  # the muscles really move the arm
    assert np.abs(got - expected[1:]).max() < 1e-9


def step(sim, command):
    sim.command(command[None])
    sim.step_block(1)
    return sim.state()[0][0]


@pytest.mark.slow
def test_an_activation_follows_its_command_as_one_minus_exp_of_t_over_tau():
    config = load_config(overrides=STILL_TOP)
    _, muscles, sim = muscled(config, arms=2)
    sim.command(np.array([[1.0, 0.0, 0.5, 0.0], [0.0, 1.0, 0.0, 0.0]]))
    sim.step_block(7)
    t, tau = 7 * config.integration.frame_dt, config.muscles.time_constant
    rise = 1 - math.exp(-t / tau)
    np.testing.assert_allclose(sim.activation(), [[rise, 0, 0.5 * rise, 0], [0, rise, 0, 0]], atol=1e-12)


def arc(rows: int, width: float, segment: float, contraction: float) -> np.ndarray:
    """Node positions (rows x 2 columns) of a ladder whose left edge is `contraction` shorter than its right one,
    bent without strain: every rung radial, the centre on the top rung's line."""
    inner = width * (1 - contraction) / contraction                # R_L: R_R / R_L = 1 / (1 - c), R_R - R_L = w
    theta = 2 * math.asin(segment / (2 * (inner + width)))         # the right edge keeps its chord
    centre = np.array([-width / 2 - inner, 0.0])
    phi = np.arange(rows) * theta
    out = np.empty((rows, 2, 2))
    for column, radius in enumerate((inner, inner + width)):
        out[:, column] = centre + radius * np.stack([np.cos(phi), -np.sin(phi)], 1)
    return out.reshape(-1, 2)


@pytest.mark.slow
def test_rest_lengths_that_imply_an_arc_bend_the_arm_onto_it():
    rows, width, length, c = 10, 0.02, 0.09, 0.2
    shape = arc(rows, width, length / (rows - 1), c)
    diagonals = list(range(rows + 2 * (rows - 1), rows + 4 * (rows - 1)))  # body.py: horizontal, vertical, diagonals
    base = {**STILL_TOP, "body.rows": rows, "body.columns": 2, "body.length": length, "body.base_width": width,
            "body.tip_width": width, "body.gravity": [0.0, 0.0], "springs.damping": 10.0,
            "integration.substeps": 100, "muscles.time_constant": 0.5,  # damped and smooth: settles in seconds
            "sensors.pairs": [[0, 2 * rows - 1]], "sensors.bend": []}
    probe = arm_batch(load_config(overrides=base)).body
    d = probe.springs[diagonals]
    diagonal = np.linalg.norm(shape[d[:, 1]] - shape[d[:, 0]], axis=1)
    assert np.ptp(diagonal) < 1e-12  # congruent cells
    c_diagonal = 1 - diagonal[0] / probe.rest_lengths[diagonals[0]]
    config = load_config(overrides={**base, "muscles.groups": [
        {"name": "edge", "side": "left", "rows": [0, rows - 1], "max_contraction": c},
        {"name": "diagonals", "springs": diagonals, "max_contraction": c_diagonal}]})
    _, _, sim = muscled(config)
    sim.command(np.ones((1, 2)))
    sim.advance(1200)
    x, v = sim.state()
    assert np.abs(v).max() < 1e-4                       # settled
    assert np.abs(x[0] - shape).max() < 1e-5            # on the arc, to 10 um
    assert shape[-1, 0] < -0.02                         # the tip 18 mm left of where it hangs straight


@pytest.mark.parametrize("group, message", [
    ({"name": "a", "side": "up", "rows": [0, 3], "max_contraction": 0.2}, "side"),
    ({"name": "a", "side": "left", "rows": [3, 3], "max_contraction": 0.2}, "rows"),
    ({"name": "a", "springs": [9999], "max_contraction": 0.2}, "springs"),
    ({"name": "a", "side": "left", "rows": [0, 3], "max_contraction": 1.0}, "max_contraction"),
    ({"name": "a", "max_contraction": 0.2}, "either side and rows, or springs"),
])
def test_a_bad_muscle_group_is_refused_naming_its_key(group, message):
    config = load_config(overrides={"muscles.groups": [group]})
    with pytest.raises(ConfigError, match=message):
        build_muscles(config, arm_batch(config).body)


def test_two_groups_cannot_move_one_spring():
    config = load_config(overrides={"muscles.groups": [
        {"name": "a", "side": "left", "rows": [0, 5], "max_contraction": 0.2},
        {"name": "b", "side": "left", "rows": [4, 8], "max_contraction": 0.2}]})
    with pytest.raises(ConfigError, match="already moves"):
        build_muscles(config, arm_batch(config).body)
