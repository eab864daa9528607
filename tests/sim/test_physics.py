"""The Taichi simulator against the NumPy reference (same scheme, float64) and against analytic physics."""

import numpy as np
import pytest

from softarm.arm.body import build_body
from softarm.arm.drive import drive_for_seed
from softarm.arm.reference import simulate_reference
from softarm.arm.statics import hanging_equilibrium
from softarm.config import load_config
from softarm.errors import SimulationError
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator
from tests.helpers.oscillator import REST_LENGTH, STILL, analytic_rates, measured_rates, one_spring, pulled
from tests.helpers.runs import assert_batch_equals_single_runs, reference_run


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])  # seed 1 checks the time offset t0 (about 51 s) too
def test_default_arm_matches_the_numpy_reference_over_five_seconds(seed):
    config, batch, expected = reference_run(seed, 500)
    x = batch.positions[0]
    got = Simulator.from_config(config, batch).advance(500)[0]
    assert np.abs(expected - x).max() > 1e-2  # the drive really moves the arm
    assert np.abs(got - expected).max() < 1e-7


@pytest.mark.slow
@pytest.mark.parametrize("direction", [[1.0, 0.0], [0.6, 0.8]])
def test_a_sum_of_sines_arm_matches_the_numpy_reference_along_any_direction(direction):
    config = load_config(overrides={"excitation.kind": "sum_of_sines", "excitation.direction": direction,
                                    "excitation.sum_of_sines.band": [0.4, 3.0], "excitation.sum_of_sines.rms": 0.003})
    batch = arm_batch(config, seeds=[0, 7])
    i = config.integration
    got = Simulator.from_config(config, batch).advance(300)
    for arm in range(2):
        drive, x, v = batch.drives[arm], batch.positions[arm], batch.velocities[arm]
        expected = simulate_reference(batch.body, drive, x, v, i.frame_dt, i.substeps, 300)
        assert np.abs(expected - x).max() > 5e-3  # the drive really moves the arm
        assert np.abs(got[arm] - expected).max() < 1e-7
        top = batch.body.driven
        offsets = (got[arm][:, top] - batch.body.rest[top]) @ np.array(direction)
        np.testing.assert_allclose(offsets, np.repeat(drive.displacement(np.arange(300) * i.frame_dt)[:, None],
                                                      len(top), 1), atol=1e-15)


@pytest.mark.slow
def test_each_arm_of_a_batch_equals_its_single_arm_run():
    assert_batch_equals_single_runs(Simulator.from_config, tolerance=1e-12)


def test_one_mass_rings_at_the_damped_frequency_and_decays_at_zeta_w0():
    body = one_spring()
    frame_dt, n_frames = 2e-4, 501  # 0.1 s, five periods, 100 samples a period
    sim = Simulator(body, drives=[STILL], frame_dt=frame_dt, substeps=4, blowup_distance=0.5,
                    positions=pulled(body, 1e-3), velocities=np.zeros((2, 2)))
    out = sim.advance(n_frames)[0]

    assert np.all(out[:, 1, 0] == 0.0)
    w_d, decay = measured_rates(np.arange(n_frames) * frame_dt, out[:, 1, 1] + REST_LENGTH)
    expected_w_d, expected_decay = analytic_rates()
    assert w_d == pytest.approx(expected_w_d, rel=5e-3)
    assert decay == pytest.approx(expected_decay, rel=1e-2)


@pytest.mark.parametrize("overrides", [{"excitation.amplitude": 50.0}, {"integration.substeps": 2}],
                         ids=["huge_amplitude", "too_few_substeps"])
def test_blow_up_stops_the_run_naming_time_node_and_substeps(overrides):
    config = load_config(overrides=overrides)
    body = build_body(config)  # not arm_batch: its stability check would refuse 2 substeps before any blow-up
    x, i = hanging_equilibrium(body), config.integration
    sim = Simulator(body, [drive_for_seed(config.excitation, 0)], i.frame_dt, i.substeps, i.blowup_distance, x,
                    np.zeros_like(x))
    with pytest.raises(SimulationError, match=r"t = \d+\.\d+ s.*node \d+.*substeps"):
        sim.advance(300)
