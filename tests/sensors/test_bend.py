"""Bend sensors: recorded on their own channel as the NumPy reference's positions bend the arm, read by the
learner recorded or recomputed alike, refused in one line where no arm can carry them; the default arm carries
four, and `[]` none."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from softarm.arm.body import build_body
from softarm.config import load_config
from softarm.errors import ConfigError, RecordingError
from softarm.model.inputs import Bend as BendInput
from softarm.record.reader import read_recording
from softarm.sense.reading import sensed_kind
from softarm.sensors import KINDS
from softarm.sensors.bend import Bend
from tests.helpers.runs import reference_run

TRIPLES = [[4, 10, 16], [16, 22, 28], [28, 34, 40], [40, 46, 55]]
CHECKER = Path(__file__).resolve().parents[3] / "shared" / "tools" / "check_recording.py"  # beside the clone


def angles(positions: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """An independent rule: the argument of the complex ratio of the two directions, less at rest."""
    z, z0 = positions[..., 0] + 1j * positions[..., 1], rest[:, 0] + 1j * rest[:, 1]
    t = np.array(TRIPLES)
    turn = lambda p: np.angle((p[..., t[:, 2]] - p[..., t[:, 1]]) / (p[..., t[:, 1]] - p[..., t[:, 0]]))  # noqa: E731
    return turn(z) - turn(z0)


def test_the_rule_reads_a_bent_arc_as_its_turning_angle():
    """Three points on a circle of radius R, a chord apart: the direction turns by the arc's angle between them."""
    radius, step = 0.2, 0.1
    phi = np.array([0.0, step, 2 * step])
    arc = np.stack([radius * np.cos(phi), radius * np.sin(phi)], axis=1)
    straight = np.array([[0.0, 0.0], [0.0, -1.0], [0.0, -2.0]])
    got = Bend().ideal(arc, straight, np.array([[0, 1, 2]]))
    np.testing.assert_allclose(got, [step], rtol=1e-12)
    mirrored = arc * [1.0, -1.0]  # bending the other way reads negative
    np.testing.assert_allclose(Bend().ideal(mirrored, straight, np.array([[0, 1, 2]])), [-step], rtol=1e-12)


@pytest.mark.slow
def test_recorded_bend_follows_the_numpy_reference_and_passes_the_shared_checker(tmp_path):
    from softarm.sim.simulate import simulate

    config, _, expected = reference_run(0, 300)
    bent = load_config(overrides={"run.duration": 3.0, "sensors.bend": TRIPLES})
    simulate(bent, tmp_path / "b.mcap")
    recording = read_recording(tmp_path / "b.mcap")
    assert recording.model["bend"] == TRIPLES
    rest = build_body(config).rest
    reference = angles(expected, rest)
    assert np.abs(reference).max() > 0.05  # the arm really bends
    np.testing.assert_allclose(recording.sensed["bend"], reference, atol=1e-6)
    np.testing.assert_allclose(recording.sensed["bend"], angles(recording.positions, rest), atol=1e-12)
    if CHECKER.exists():
        done = subprocess.run([sys.executable, str(CHECKER), str(tmp_path / "b.mcap")], capture_output=True, text=True)
        assert done.returncode == 0, done.stdout + done.stderr


@pytest.mark.slow
def test_the_learner_reads_recorded_and_recomputed_bend_alike_and_the_default_arm_carries_four(tmp_path):
    from softarm.sim.simulate import simulate

    simulate(load_config(overrides={"run.duration": 1.0, "sensing.bend_noise": 0.0}), tmp_path / "b.mcap")
    simulate(load_config(overrides={"run.duration": 1.0, "sensors.bend": []}), tmp_path / "plain.mcap")
    recorded, plain = read_recording(tmp_path / "b.mcap"), read_recording(tmp_path / "plain.mcap")
    assert recorded.model["bend"] == TRIPLES
    recomputed = load_config(overrides={"sensing.bend": TRIPLES})
    np.testing.assert_array_equal(sensed_kind(recorded, Bend(), load_config().sensing),
                                  sensed_kind(recorded, Bend(), recomputed.sensing))
    assert "bend" not in plain.model and plain.sensed == {}
    np.testing.assert_array_equal(BendInput().read(plain, recomputed),
                                  sensed_kind(recorded, Bend(), recomputed.sensing))
    assert (BendInput().features(plain.model, recomputed) == 4
            and BendInput().features(recorded.model, load_config()) == 4)
    with pytest.raises(RecordingError, match="has no bend sensors: record them"):
        BendInput().read(plain, load_config())
    noisy = load_config(overrides={"sensing.bend": TRIPLES, "sensing.bend_noise": 0.01}).sensing
    spread = (sensed_kind(plain, Bend(), noisy) - sensed_kind(plain, Bend(), recomputed.sensing)).std()
    assert 0.008 < spread < 0.012


@pytest.mark.parametrize("triples, message", [([[4, 4, 16]], "three different nodes"),
                                              ([[4, 10, 57]], "outside the arm's 0..56"),
                                              ([[4, 10]], "must be a list of")])
def test_a_bend_sensor_no_arm_can_carry_is_refused_in_one_line(triples, message):
    with pytest.raises(ConfigError, match=message):
        build_body(load_config(overrides={"sensors.bend": triples}))


def test_every_kind_declares_what_its_channel_needs():
    for name, kind in KINDS.items():
        assert kind.name == name and kind.topic.startswith("/arm/") and kind.unit and kind.width >= 2
