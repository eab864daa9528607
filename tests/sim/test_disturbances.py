"""Disturbances in the physics: the Taichi simulator against the NumPy reference for every kind, against closed
forms on one spring, batched beside undisturbed arms, and the stability limit with contacts and stiffening."""

import dataclasses

import numpy as np
import pytest

from softarm.arm.reference import simulate_reference
from softarm.config import load_config
from softarm.disturbances import Drag, Obstacle, Payload, Push, Stiffness
from softarm.errors import ConfigError
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator
from tests.helpers.oscillator import MASS, REST_LENGTH, STIFFNESS, STILL, analytic_rates, measured_rates, one_spring

TIP = [54, 55, 56]
ONE_OF_EACH = {
    "push": {"kind": "push", "start": 0.3013, "end": 0.5013, "force": [0.2, 0.05], "nodes": TIP},
    "payload": {"kind": "payload", "start": 0.6013, "mass": 0.02, "nodes": TIP},
    "stiffness": {"kind": "stiffness", "start": 0.2013, "end": 1.5013, "factor": 0.3, "springs": list(range(40, 60))},
    "obstacle": {"kind": "obstacle", "start": 0.0, "centre": [0.035, -0.15], "radius": 0.02},
    "drag": {"kind": "drag", "start": 0.1013, "velocity": [0.05, 0.01], "coefficient": 0.02, "quadratic": 0.3},
}


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(ONE_OF_EACH))
def test_every_kind_matches_the_numpy_reference_over_two_seconds(kind):
    config = load_config(overrides={"disturbances": [ONE_OF_EACH[kind]], "excitation.amplitude": 0.006})
    batch = arm_batch(config, seeds=[0])
    i = config.integration
    sim = Simulator.from_config(config, batch)
    got = sim.advance(200)[0]
    sim.close()
    args = (batch.body, batch.drives[0], batch.positions[0], batch.velocities[0], i.frame_dt, i.substeps, 200)
    expected, undisturbed = simulate_reference(*args, batch.disturbances[0]), simulate_reference(*args)
    assert np.abs(expected - undisturbed).max() > 1e-3  # the disturbance really acts
    assert np.abs(got - expected).max() < 1e-9


@pytest.mark.slow
def test_a_batch_of_disturbed_and_undisturbed_arms_equals_its_single_arm_runs():
    config = load_config(overrides={"world.random": [
        {"kind": "push", "share": 0.5, "count": [1, 2], "start": [0.1, 0.8], "duration": [0.05, 0.2],
         "force": [0.05, 0.3], "rows": [10, 18]}], "run.arms": 3, "run.seed": 2})
    batch = arm_batch(config)
    assert 0 < sum(map(bool, batch.disturbances)) < 3  # some arms drew pushes, some none
    sim = Simulator.from_config(config, batch)
    together = sim.advance(100)
    sim.close()
    for a, seed in enumerate(batch.seeds):
        alone = Simulator.from_config(config, arm_batch(config, seeds=[seed]))
        assert np.abs(alone.advance(100)[0] - together[a]).max() < 1e-12
        alone.close()


def spring(gravity: float = 0.0, damping: float = 0.9):
    return dataclasses.replace(one_spring(damping), gravity=np.array([0.0, -gravity]))


def settle(body, disturbances, seconds=1.0, frame_dt=1e-3):
    sim = Simulator(body, drives=[STILL], frame_dt=frame_dt, substeps=4, blowup_distance=0.5, positions=body.rest,
                    velocities=np.zeros((2, 2)), disturbances=[disturbances])
    out = sim.advance(round(seconds / frame_dt) + 1)[0]
    sim.close()
    return out


@pytest.mark.slow
def test_a_constant_push_stretches_the_spring_by_force_over_stiffness():
    out = settle(spring(), [Push(0.0, None, (0.0, -0.5), (1,))])
    assert out[-1, 1, 1] == pytest.approx(-REST_LENGTH - 0.5 / STIFFNESS, abs=1e-10)


@pytest.mark.slow
def test_a_payload_hangs_the_mass_lower_and_rings_slower():
    payload = 0.02
    hung = settle(spring(gravity=9.81), [Payload(0.0, None, payload, (1,))])
    assert hung[-1, 1, 1] == pytest.approx(-REST_LENGTH - (MASS + payload) * 9.81 / STIFFNESS, abs=1e-10)
    rings = settle(spring(), [Payload(0.0, None, payload, (1,)), Push(0.0, 0.001, (0.0, -2.0), (1,))], 0.1, 2e-4)
    w_d, _ = measured_rates(np.arange(len(rings)) * 2e-4, rings[:, 1, 1] + REST_LENGTH)
    zeta = 0.9 / (2 * np.sqrt(STIFFNESS * (MASS + payload)))
    assert w_d == pytest.approx(np.sqrt(STIFFNESS / (MASS + payload)) * np.sqrt(1 - zeta ** 2), rel=5e-3)


@pytest.mark.slow
def test_a_softened_spring_rings_at_the_frequency_of_its_stiffness():
    factor = 0.25
    rings = settle(spring(), [Stiffness(0.0, None, factor, (0,)), Push(0.0, 0.001, (0.0, -2.0), (1,))], 0.1, 2e-4)
    w_d, decay = measured_rates(np.arange(len(rings)) * 2e-4, rings[:, 1, 1] + REST_LENGTH)
    expected = analytic_rates()[1]  # the damper is unchanged: the decay rate b / 2m stays
    zeta = 0.9 / (2 * np.sqrt(factor * STIFFNESS * MASS))
    assert w_d == pytest.approx(np.sqrt(factor * STIFFNESS / MASS) * np.sqrt(1 - zeta ** 2), rel=5e-3)
    assert decay == pytest.approx(expected, rel=2e-2)


@pytest.mark.slow
def test_a_node_pushed_into_a_wall_stops_where_spring_and_contact_balance_the_push():
    wall = -REST_LENGTH - 2e-4  # the wall's surface, 0.2 mm below the mass at rest
    disc = Obstacle(0.0, None, (0.0, wall - 1.0), 1.0, 2000.0, 0.5)  # radius 1 m: flat where the mass meets it
    out = settle(spring(), [Push(0.0, None, (0.0, -0.5), (1,)), disc])
    depth = (0.5 - STIFFNESS * 2e-4) / (STIFFNESS + 2000.0)
    assert out[-1, 1, 1] == pytest.approx(wall - depth, abs=1e-10)


@pytest.mark.slow
def test_a_current_holds_the_mass_where_the_spring_balances_the_drag():
    """Along the spring's line, a current u = 0.3 m/s pulls the still mass with (c + c2 |u|) u: linear and
    quadratic terms both count, and the spring stretches by that over k."""
    c, c2, u = 0.02, 0.1, 0.3
    out = settle(spring(), [Drag(0.0, None, (0.0, -u), c, c2)], seconds=2.0)
    assert out[-1, 1, 1] == pytest.approx(-REST_LENGTH - (c + c2 * u) * u / STIFFNESS, abs=1e-10)


@pytest.mark.slow
def test_still_water_damps_the_ring_by_the_drag_coefficient():
    """Linear drag in still water is a damper to a fixed point: the decay rate b / 2m becomes (b + c) / 2m."""
    c = 0.6
    rings = settle(spring(), [Drag(0.0, None, (0.0, 0.0), c, 0.0), Push(0.0, 0.001, (0.0, -2.0), (1,))], 0.1, 2e-4)
    w_d, decay = measured_rates(np.arange(len(rings)) * 2e-4, rings[:, 1, 1] + REST_LENGTH)
    assert decay == pytest.approx(analytic_rates(0.9 + c)[1], rel=2e-2)
    assert w_d == pytest.approx(analytic_rates(0.9 + c)[0], rel=5e-3)


def test_contact_and_stiffening_lower_the_stable_step():
    stiff = {"kind": "obstacle", "start": 0.0, "centre": [0.05, -0.1], "radius": 0.01, "stiffness": 2e6}
    with pytest.raises(ConfigError, match="integration.substeps.*disturbances"):
        arm_batch(load_config(overrides={"disturbances": [stiff]}))
    harder = {"kind": "stiffness", "start": 1.0, "factor": 200.0, "springs": [10]}
    with pytest.raises(ConfigError, match="integration.substeps"):
        arm_batch(load_config(overrides={"disturbances": [harder]}))
    arm_batch(load_config(overrides={"disturbances": [{**harder, "factor": 0.1}]}))  # softening is always stable


def test_a_batch_checks_each_arm_with_its_own_disturbances():
    """Arms never touch one another: 64 arms, each with the same disc, are as stable as one of them (the check
    once summed every arm's contacts and refused such a batch)."""
    disc = {"kind": "obstacle", "start": 0.0, "centre": [0.05, -0.15], "radius": 0.02}
    assert arm_batch(load_config(overrides={"disturbances": [disc]}), seeds=range(64)).arms == 64
    stiff = {**disc, "stiffness": 2e6}
    with pytest.raises(ConfigError, match="integration.substeps"):
        arm_batch(load_config(overrides={"disturbances": [stiff]}), seeds=range(64))


def test_a_drag_is_refused_in_one_line_naming_its_key():
    def refused(overrides: dict, key: str, words: str) -> None:
        with pytest.raises(ConfigError, match=f"{key}.*{words}"):
            arm_batch(load_config(overrides=overrides))

    water = {"kind": "drag", "start": 0.0, "coefficient": 0.02}
    refused({"disturbances": [{**water, "coefficient": -0.1}]}, r"disturbances\[0\].coefficient", ">= 0")
    refused({"disturbances": [{**water, "quadratic": -1.0}]}, r"disturbances\[0\].quadratic", ">= 0")
    refused({"disturbances": [{**water, "nodes": [55]}]}, r"disturbances\[0\].nodes", "a drag takes")
    refused({"disturbances": [{"kind": "drag", "start": 0.0}]}, r"disturbances\[0\].coefficient", "missing")
    current = {"kind": "drag", "share": 1.0, "count": [1, 1], "start": [0.0, 1.0], "speed": [0.0, 0.1],
               "coefficient": [0.01, 0.02]}
    refused({"world.random": [{**current, "rows": [3, 5]}]}, r"world.random\[0\].rows", "a random drag takes")
    refused({"world.random": [{**current, "speed": [0.2, 0.1]}]}, r"world.random\[0\].speed", "min <= max")
    poke = {"kind": "push", "share": 1.0, "count": [1, 1], "start": [0.0, 1.0], "force": [0.01, 0.02]}
    refused({"world.random": [poke]}, r"world.random\[0\].rows", "missing")
    drawn = arm_batch(load_config(overrides={"world.random": [current], "run.arms": 2})).disturbances
    assert all(len(arm) == 1 and isinstance(arm[0], Drag) and 0 <= np.hypot(*arm[0].velocity) <= 0.1
               and 0.01 <= arm[0].coefficient <= 0.02 and arm[0].quadratic == 0.0 for arm in drawn)
