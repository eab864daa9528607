"""Reading any node pairs: the simulator's sensor rule, checked pairs, and a recording's own stretch
recomputed from its node positions."""

import numpy as np
import pytest

from softarm.arm.sensors import stretch
from softarm.config import load_config
from softarm.errors import RecordingError
from softarm.record.format import POSITION_DECIMALS
from softarm.record.reader import read_recording
from softarm.sense.pairs import recording_stretch, stretch_for_pairs


@pytest.fixture(scope="module")
def recording_path(tmp_path_factory):
    """A 0.5 s recording of the default arm."""
    from softarm.sim.simulate import simulate

    path = tmp_path_factory.mktemp("sense") / "r.mcap"
    simulate(load_config(overrides={"run.duration": 0.5}), path)
    return path


@pytest.fixture(scope="module")
def recording(recording_path):
    return read_recording(recording_path)


def test_three_node_stretch_matches_a_hand_computation():
    rest = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    positions = np.array([rest, [[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]]])
    readings = stretch_for_pairs(positions, rest, np.array([[0, 1], [1, 2], [2, 0]]))
    assert readings.dtype == np.float64
    np.testing.assert_allclose(readings, [[0.0, 0.0, 0.0], [1.0, 0.0, -1.0]], rtol=0, atol=1e-15)


@pytest.mark.slow
def test_stretch_for_pairs_is_the_simulators_sensor_rule(recording):
    rest, pairs = np.array(recording.model["nodes"]), np.array(recording.model["sensors"])
    positions = recording.positions
    assert np.array_equal(stretch_for_pairs(positions, rest, pairs), stretch(positions, rest, pairs))


def test_pairs_given_as_lists_are_read_like_arrays(recording):
    rest = np.array(recording.model["nodes"])
    assert np.array_equal(stretch_for_pairs(recording.positions, rest, ((3, 27), (5, 29))),
                          stretch_for_pairs(recording.positions, rest, np.array([[3, 27], [5, 29]])))


@pytest.mark.parametrize("bad, named", [([3, 99], "names node 99"), ([-1, 4], "names node -1"),
                                        ([4, 4], "node 4 to itself")])
def test_a_pair_no_arm_has_is_refused_naming_it(bad, named):
    rest = np.zeros((57, 2))
    with pytest.raises(RecordingError) as e:
        stretch_for_pairs(np.zeros((1, 57, 2)), rest, [[0, 1], [2, 3], bad])
    message = str(e.value)
    assert "\n" not in message and f"sensing.pairs[2] = {bad}" in message and named in message
    if bad[0] != bad[1]:
        assert "nodes 0..56" in message


def test_no_pairs_reads_the_recorded_stretch(recording):
    for pairs in (None, [], ()):
        out = recording_stretch(recording, pairs)
        assert out.dtype == np.float64 and np.array_equal(out, recording.stretch)


def test_the_recordings_own_pairs_recompute_its_stretch(recording):
    # Positions are written rounded to 10**-POSITION_DECIMALS m: each coordinate moves by at most half of
    # that, so a distance between two nodes by at most sqrt(2) times it (the recorded stretch is exact).
    out = recording_stretch(recording, recording.model["sensors"])
    assert out.shape == recording.stretch.shape
    np.testing.assert_allclose(out, recording.stretch, rtol=0, atol=np.sqrt(2) * 10.0**-POSITION_DECIMALS)


def test_other_pairs_need_the_node_positions(recording_path):
    without_nodes = read_recording(recording_path, nodes=False)
    assert np.array_equal(recording_stretch(without_nodes, []), without_nodes.stretch)
    with pytest.raises(RecordingError, match="without node positions"):
        recording_stretch(without_nodes, [[3, 27]])
