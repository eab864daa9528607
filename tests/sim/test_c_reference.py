"""The benchmark's hand-written C physics against the NumPy reference: it must compute the same run."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))  # bench/ is not a package

from c_reference import CReference, find_compiler  # noqa: E402
from runs import assert_batch_equals_single_runs  # noqa: E402
from softarm.arm.batch import arm_batch  # noqa: E402
from softarm.arm.reference import simulate_reference  # noqa: E402
from softarm.config import load_config  # noqa: E402

pytestmark = pytest.mark.skipif(find_compiler() is None, reason="no C compiler (cc or gcc) on PATH")


@pytest.mark.parametrize("seed", [0, 1])  # seed 1 checks the time offset t0 too
def test_c_reference_matches_the_numpy_reference_over_two_seconds(seed):
    config = load_config()
    batch = arm_batch(config, seeds=[seed])
    x, v = batch.positions[0], batch.velocities[0]
    i = config.integration
    expected = simulate_reference(batch.body, batch.drives[0], x, v, i.frame_dt, i.substeps, 200)
    sim = CReference.from_config(config, batch)
    got = np.concatenate([sim.advance(120), sim.advance(80)], axis=1)[0]  # two calls: the frame count carries on
    assert np.abs(expected - x).max() > 1e-3  # the drive really moves the arm
    assert np.abs(got - expected).max() < 1e-9


def test_each_arm_of_a_c_batch_equals_its_single_arm_run():
    assert_batch_equals_single_runs(CReference.from_config, tolerance=0.0)
