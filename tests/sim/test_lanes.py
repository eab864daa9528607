"""Arms stepped side by side in a group (sim/forces.py) equal, bit for bit, the same arms stepped alone: the lanes
change the speed, never the numbers."""

import numpy as np
import pytest

from softarm.arm.batch import arm_batch
from softarm.arm.disturbances import Push
from softarm.arm.muscles import build_muscles
from softarm.config import load_config
from softarm.sim import physics
from softarm.sim.physics import Simulator
from tests.sim.test_disturbances import ONE_OF_EACH

ARMS = 8


@pytest.fixture
def four_lanes(monkeypatch):
    """Groups of four arms (one arm alone in its own), whatever the machine's thread count would choose."""
    monkeypatch.setattr(physics, "lane_layout", lambda arms: (4, arms // 4) if arms % 4 == 0 else (1, arms))


def alone(config, seed, muscles=None, commands=None, frames=120):
    sim = Simulator.from_config(config, arm_batch(config, seeds=[seed]), muscles=muscles)
    assert sim.lanes == 1
    out = run(sim, commands, frames)[0]
    sim.close()
    return out


def run(sim, commands, frames):
    if commands is None:
        return sim.advance(frames)
    out = []
    for u in commands:
        sim.command(u)
        out.append(sim.advance(1))
    return np.concatenate(out, axis=1)


def test_a_group_of_disturbed_and_undisturbed_arms_equals_each_arm_alone(four_lanes):
    config = load_config(overrides={"world.random": [
        {"kind": "push", "share": 0.5, "count": [1, 2], "start": [0.1, 0.8], "duration": [0.05, 0.2],
         "force": [0.05, 0.3], "rows": [10, 18]}], "disturbances": [ONE_OF_EACH[k] for k in ("stiffness", "payload", "obstacle")],
        "run.arms": ARMS, "run.seed": 2, "excitation.amplitude": 0.006})
    batch = arm_batch(config)
    pushed = [any(d.code == Push.code for d in arm) for arm in batch.disturbances]
    assert any(pushed) and not all(pushed)
    sim = Simulator.from_config(config, batch)
    assert sim.lanes == 4
    together = sim.advance(120)
    sim.close()
    for a in {pushed.index(True), pushed.index(False), ARMS - 1}:  # pushed, not pushed, the last lane of the last group
        np.testing.assert_array_equal(together[a], alone(config, batch.seeds[a]))
    assert np.abs(together[1] - together[0]).max() > 1e-3  # the arms really differ


def test_a_group_of_commanded_arms_equals_each_arm_alone(four_lanes):
    config = load_config(overrides={"excitation.amplitude": 0.003})
    batch = arm_batch(config, seeds=range(ARMS))
    muscles = build_muscles(config, batch.body)
    commands = np.random.default_rng(5).uniform(0, 1, (12, ARMS, muscles.count)).repeat(5, axis=0)
    sim = Simulator.from_config(config, batch, muscles=muscles)
    assert sim.lanes == 4
    together = run(sim, commands, 0)
    sim.close()
    for a in (2, ARMS - 1):
        np.testing.assert_array_equal(together[a], alone(config, a, muscles, commands[:, a:a + 1]))
