"""Which node pairs are read: the recording's own sensors, or any others recomputed from its node positions."""

from typing import TYPE_CHECKING, Optional, Sequence, Union

import numpy as np

from softarm.arm.sensors import stretch
from softarm.errors import RecordingError
from softarm.record.recording import needs_nodes_error

if TYPE_CHECKING:
    from softarm.record.reader import Recording

Pairs = Union[np.ndarray, Sequence[Sequence[int]]]


def stretch_for_pairs(positions: np.ndarray, rest: np.ndarray, pairs: Pairs) -> np.ndarray:
    """(T, P) float64 readings of the pairs (P, 2) for positions (T, N, 2) m and rest positions (N, 2) m.

    The same rule as the simulator's sensors (`softarm.arm.sensors.stretch`); the pairs are checked
    first, because NumPy would read a negative index from the other end instead of refusing it.
    """
    pairs = _checked(pairs, len(rest))
    return stretch(np.asarray(positions, np.float64), np.asarray(rest, np.float64), pairs)


def recording_stretch(recording: "Recording", pairs: Optional[Pairs]) -> np.ndarray:
    """The (T, P) stretch the learner reads: the recorded one for no pairs, else recomputed from node positions."""
    if pairs is None or len(pairs) == 0:
        return np.asarray(recording.stretch, np.float64)
    if recording.positions is None:
        raise needs_nodes_error(recording, "sensing.pairs (the stretch of other node pairs, recomputed)")
    return stretch_for_pairs(recording.positions, np.asarray(recording.model["nodes"], np.float64), pairs)


def _checked(pairs: Pairs, n_nodes: int) -> np.ndarray:
    """Pairs as a (P, 2) int array, refusing, with a one-line message naming it, a pair no arm can have."""
    pairs = np.asarray(pairs, np.int64)
    if pairs.size == 0:
        pairs = pairs.reshape(0, 2)
    if pairs.ndim != 2 or pairs.shape[1] != 2:
        raise RecordingError(f"sensing.pairs must be a list of [a, b] node pairs, not an array of shape {pairs.shape}")
    for k, (a, b) in enumerate(pairs.tolist()):
        for node in (a, b):
            if not 0 <= node < n_nodes:
                raise RecordingError(f"sensing.pairs[{k}] = [{a}, {b}] names node {node}, but the recording's arm "
                                     f"has nodes 0..{n_nodes - 1}")
        if a == b:
            raise RecordingError(f"sensing.pairs[{k}] = [{a}, {b}] joins node {a} to itself: a sensor needs two "
                                 "different nodes")
    return pairs
