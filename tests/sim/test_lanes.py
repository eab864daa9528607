"""Arms stepped side by side in a group (sim/forces.py) equal, bit for bit, the same arms stepped alone: the lanes
change the speed, never the numbers."""

import numpy as np
import pytest
import taichi as ti

from softarm.config import load_config
from softarm.sim import layout
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


ARMS = 8
EXCITATIONS = {
    "product_of_sines": {},
    "sum_of_sines": {"excitation.kind": "sum_of_sines", "excitation.direction": [0.6, 0.8],
                     "excitation.sum_of_sines.band": [0.4, 3.0], "excitation.sum_of_sines.rms": 0.003},
}


@pytest.fixture
def four_lanes(monkeypatch):
    """Groups of four plain arms (one arm alone in its own), whatever the machine's thread count would choose."""
    monkeypatch.setattr(layout, "lane_layout",
                        lambda arms, plain: (4, arms // 4) if plain and arms % 4 == 0 else (1, arms))


@pytest.mark.parametrize("excitation", list(EXCITATIONS))
def test_a_group_of_arms_equals_each_arm_alone(four_lanes, excitation):
    config = load_config(overrides=EXCITATIONS[excitation])
    sim = Simulator.from_config(config, arm_batch(config, seeds=range(ARMS)))
    assert sim.lanes == 4
    together = sim.advance(150)
    sim.close()
    for a in (2, ARMS - 1):  # a middle lane of the first group, the last lane of the last
        alone = Simulator.from_config(config, arm_batch(config, seeds=[a]))
        assert alone.lanes == 1
        np.testing.assert_array_equal(together[a], alone.advance(150)[0])
        alone.close()
    assert np.abs(together[1] - together[0]).max() > 1e-3  # the arms really differ


def test_only_a_plain_batch_of_enough_arms_is_stepped_in_lanes():
    config = load_config(overrides={"disturbances": [{"kind": "payload", "start": 0.1, "mass": 0.01, "nodes": [56]}]})
    threads = ti.lang.impl.current_cfg().cpu_max_num_threads
    plain, disturbed = (Simulator.from_config(c, arm_batch(c, seeds=range(4 * threads)))
                        for c in (load_config(), config))
    assert (plain.lanes, disturbed.lanes) == (4, 1)
    plain.close()
    disturbed.close()
