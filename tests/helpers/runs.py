"""Checks shared by the tests of the two physics engines (the Taichi simulator and the C reference)."""

import numpy as np

from softarm.arm.reference import simulate_reference
from softarm.config import load_config
from softarm.sim.batch import arm_batch


def reference_run(seed: int, n_frames: int):
    """(config, batch, expected): the default arm with this seed, started as a real run starts it, and the
    float64 NumPy reference's positions of its first n_frames frames."""
    config = load_config()
    batch = arm_batch(config, seeds=[seed])
    i = config.integration
    expected = simulate_reference(batch.body, batch.drives[0], batch.positions[0], batch.velocities[0], i.frame_dt,
                                  i.substeps, n_frames)
    return config, batch, expected


def assert_batch_equals_single_runs(make_run, tolerance: float) -> None:
    """Each arm of a 3-arm batch equals a single-arm run with its seed (to `tolerance`), and the arms differ.

    `make_run(config, batch)` builds an engine for an `ArmBatch`; `.advance(n)` returns (arms, n, N, 2).
    """
    config = load_config()
    batch = make_run(config, arm_batch(config, seeds=range(3))).advance(150)
    for arm in range(3):
        single = make_run(config, arm_batch(config, seeds=[arm])).advance(150)[0]
        assert np.abs(batch[arm] - single).max() <= tolerance
    assert np.abs(batch[1] - batch[0]).max() > 1e-3  # the seeds really differ
