"""The default step is converged: MODEL.md asks < 0.1 mm against a 4x finer run (README has the 100 s study)."""

import numpy as np

from softarm.body import build_body, hanging_equilibrium
from softarm.config import load_config
from softarm.excitation import drive_for_seed
from softarm.physics import Simulator


def positions(config, substeps: int, n_frames: int) -> np.ndarray:
    body = build_body(config)
    x = hanging_equilibrium(body)
    i = config.integration
    drives = [drive_for_seed(config.excitation, seed) for seed in (0, 1)]
    return Simulator(body, drives, i.frame_dt, substeps, i.blowup_distance, x, np.zeros_like(x)).advance(n_frames)


def test_default_substeps_are_converged_against_a_four_times_finer_run():
    config = load_config()
    n = config.integration.substeps
    coarse, fine = positions(config, n, 1000), positions(config, 4 * n, 1000)  # 10 s, seeds 0 and 1
    error = np.linalg.norm(coarse - fine, axis=-1).max()
    assert np.abs(coarse - coarse[:, :1]).max() > 0.02  # the arm swings by centimetres meanwhile
    assert error < 1e-4, f"{error * 1e3:.4f} mm"


def test_error_shrinks_in_proportion_to_the_step():
    # Semi-implicit Euler is first order: halving the step halves the error against a fine run.
    config = load_config()
    n = config.integration.substeps
    fine = positions(config, 8 * n, 300)
    e1 = np.abs(positions(config, n, 300) - fine).max()
    e2 = np.abs(positions(config, 2 * n, 300) - fine).max()
    assert 1.6 < e1 / e2 < 2.6, (e1, e2)
