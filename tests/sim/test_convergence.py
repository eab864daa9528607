"""The default step is converged: docs/model.md asks < 0.1 mm against a 4x finer run (README has the 100 s study)."""

import numpy as np
import pytest

from softarm.config import load_config, override
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def positions(config, substeps: int, n_frames: int) -> np.ndarray:
    """Seeds 0 and 1 started as a real run starts them, stepped with `substeps`."""
    config = override(config, {"integration.substeps": substeps})
    return Simulator.from_config(config, arm_batch(config, seeds=(0, 1))).advance(n_frames)


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
