"""The benchmark's hand-written C physics against the NumPy reference: it must compute the same run."""

import numpy as np
import pytest

from bench.c_reference import CReference, find_compiler
from tests.helpers.runs import assert_batch_equals_single_runs, reference_run

pytestmark = pytest.mark.skipif(find_compiler() is None, reason="no C compiler (cc or gcc) on PATH")


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])  # seed 1 checks the time offset t0 too
def test_c_reference_matches_the_numpy_reference_over_two_seconds(seed):
    config, batch, expected = reference_run(seed, 200)
    x = batch.positions[0]
    sim = CReference.from_config(config, batch)
    got = np.concatenate([sim.advance(120), sim.advance(80)], axis=1)[0]  # two calls: the frame count carries on
    assert np.abs(expected - x).max() > 1e-3  # the drive really moves the arm
    assert np.abs(got - expected).max() < 1e-9


def test_each_arm_of_a_c_batch_equals_its_single_arm_run():
    assert_batch_equals_single_runs(CReference.from_config, tolerance=0.0)
