"""The NumPy reference against analytic physics: if it passes these, it can judge the Taichi simulator."""

import numpy as np
import pytest

from softarm.arm.body import build_body
from softarm.arm.drive import drive_for_seed
from softarm.arm.reference import simulate_reference
from softarm.arm.statics import hanging_equilibrium
from softarm.config import load_config, override
from tests.helpers.oscillator import (
    MASS,
    REST_LENGTH,
    STIFFNESS,
    STILL,
    analytic_rates,
    measured_rates,
    one_spring,
    pulled,
)


def test_one_mass_rings_at_the_damped_frequency_and_decays_at_zeta_w0():
    body = one_spring()
    frame_dt, n_frames = 2e-4, 501  # 0.1 s, five periods, 100 samples a period
    out = simulate_reference(body, STILL, pulled(body, 1e-3), np.zeros((2, 2)), frame_dt, 4, n_frames)

    assert np.all(out[:, 1, 0] == 0.0)  # pulled along the spring, it stays on the spring's line
    w_d, decay = measured_rates(np.arange(n_frames) * frame_dt, out[:, 1, 1] + REST_LENGTH)
    expected_w_d, expected_decay = analytic_rates()
    assert w_d == pytest.approx(expected_w_d, rel=5e-3)
    assert decay == pytest.approx(expected_decay, rel=1e-2)


def test_arm_started_at_its_hanging_equilibrium_stays_put():
    config = load_config()
    body = build_body(config)
    still = drive_for_seed(override(config, {"excitation.amplitude": 0.0}).excitation, 0)
    x = hanging_equilibrium(body)
    out = simulate_reference(body, still, x, np.zeros_like(x), config.integration.frame_dt,
                             config.integration.substeps, 50)
    assert np.abs(out - x).max() < 1e-9


@pytest.mark.slow
def test_undamped_spring_keeps_its_energy_over_many_periods():
    # A stretching, swinging spring in the plane (node 1 pulled out and pushed sideways).
    body = one_spring(damping=0.0)
    x = pulled(body, 2e-3)
    v = np.array([[0.0, 0.0], [0.3, 0.0]])
    h, n_steps = 2.5e-5, 40_000  # 1 s: about 50 periods of the stretch
    # One step a frame, so the frames are every step and v_n = (x_n - x_(n-1)) / h exactly.
    out = simulate_reference(body, STILL, x, v, h, 1, n_steps + 1)[:, 1]

    velocity = np.diff(out, axis=0) / h
    stretch = np.linalg.norm(out[1:], axis=1) - REST_LENGTH
    energy = 0.5 * MASS * (velocity ** 2).sum(axis=1) + 0.5 * STIFFNESS * stretch ** 2
    first, last = energy[: n_steps // 10].mean(), energy[-n_steps // 10:].mean()
    assert np.abs(energy / energy[0] - 1).max() < 1e-2   # bounded wobble, O(w h)
    assert abs(last / first - 1) < 1e-3                  # and no drift
