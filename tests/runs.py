"""Checks shared by the tests of the two physics engines (the Taichi simulator and the C reference)."""

import numpy as np

from softarm.config import load_config
from softarm.excitation import drive_for_seed


def assert_batch_equals_single_runs(make_run, tolerance: float) -> None:
    """Each arm of a 3-arm batch equals a single-arm run with its drive (to `tolerance`), and the arms differ.

    `make_run(config, drives)` builds an engine with one arm per drive; `.advance(n)` returns (arms, n, N, 2).
    """
    config = load_config()
    drives = [drive_for_seed(config.excitation, seed) for seed in range(3)]
    batch = make_run(config, drives).advance(150)
    for arm, drive in enumerate(drives):
        single = make_run(config, [drive]).advance(150)[0]
        assert np.abs(batch[arm] - single).max() <= tolerance
    assert np.abs(batch[1] - batch[0]).max() > 1e-3  # the seeds really differ
