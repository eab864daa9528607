"""The benchmark's hand-written C physics against the NumPy reference: it must compute the same run."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))  # bench/ is not a package

from c_reference import CReference, find_compiler  # noqa: E402
from runs import assert_batch_equals_single_runs  # noqa: E402
from softarm.body import build_body, hanging_equilibrium  # noqa: E402
from softarm.config import load_config  # noqa: E402
from softarm.excitation import drive_for_seed  # noqa: E402
from softarm.reference import simulate_reference  # noqa: E402

pytestmark = pytest.mark.skipif(find_compiler() is None, reason="no C compiler (cc or gcc) on PATH")


def hanging_run(config, drives):
    """A CReference of the config's body, hanging at rest at t = 0, one arm per drive."""
    body = build_body(config)
    x = hanging_equilibrium(body)
    i = config.integration
    return CReference(body, drives, i.frame_dt, i.substeps, x, np.zeros_like(x))


@pytest.mark.parametrize("seed", [0, 1])  # seed 1 checks the time offset t0 too
def test_c_reference_matches_the_numpy_reference_over_two_seconds(seed):
    config = load_config()
    body, drive = build_body(config), drive_for_seed(config.excitation, seed)
    x = hanging_equilibrium(body)
    i = config.integration
    expected = simulate_reference(body, drive, x, np.zeros_like(x), i.frame_dt, i.substeps, 200)
    sim = hanging_run(config, [drive])
    got = np.concatenate([sim.advance(120), sim.advance(80)], axis=1)[0]  # two calls: the frame count carries on
    assert np.abs(expected - x).max() > 1e-3  # the drive really moves the arm
    assert np.abs(got - expected).max() < 1e-9


def test_each_arm_of_a_c_batch_equals_its_single_arm_run():
    assert_batch_equals_single_runs(hanging_run, tolerance=0.0)
