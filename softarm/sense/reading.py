"""What a learner reads from a recording: the stretch of the configured pairs, or another sensor kind's readings
(softarm.sensors), with the configured imperfections, one realisation per recording (its simulation seed is the
noise stream).

Training, replay and evaluation all read through `sensed_stretch`, so a checkpoint imagines from
exactly the kind of signal it was trained on, unless a caller asks for another sensor model.
"""

from typing import TYPE_CHECKING, Any

import numpy as np

from softarm.config import SensingConfig
from softarm.errors import RecordingError
from softarm.record.recording import needs_nodes_error
from softarm.sense.imperfections import SensorModel
from softarm.sense.pairs import recording_stretch
from softarm.sensors import SensorKind

if TYPE_CHECKING:
    from softarm.record.reader import Recording


def sensed_stretch(recording: "Recording", sensing: SensingConfig) -> np.ndarray:
    """(T, P) float64 readings of `recording` as `sensing` reads them."""
    ideal = recording_stretch(recording, sensing.pairs)
    return SensorModel.from_config(sensing).apply(ideal, recording.times, stream=int(recording.model.get("seed", 0)))


def needs_nodes(sensing: SensingConfig) -> bool:
    """Other pairs than the recorded ones are recomputed from the node positions."""
    return bool(sensing.pairs)


def sensor_count(model: dict[str, Any], sensing: SensingConfig) -> int:
    """How many signals a learner reads from a recording with this model document."""
    return len(sensing.pairs) if sensing.pairs else len(model["sensors"])


def sensed_kind(recording: "Recording", kind: SensorKind, sensing: SensingConfig) -> np.ndarray:
    """(T, S) float64 readings of another sensor kind: recomputed from the node positions where [sensing] places
    the kind's sensors, else the recording's own; with the kind's imperfections."""
    placements = getattr(sensing, kind.name)
    if placements:
        if recording.positions is None:
            raise needs_nodes_error(recording, f"sensing.{kind.name} (the {kind.name} sensors, recomputed)")
        rest = np.asarray(recording.model["nodes"], np.float64)
        ideal = kind.ideal(recording.positions, rest, kind.check(placements, len(rest), f"sensing.{kind.name}"))
    elif kind.name in recording.sensed:
        ideal = recording.sensed[kind.name]
    else:
        raise RecordingError(f"{recording.path} has no {kind.name} sensors: record them ([sensors] {kind.name}) or "
                             f"place them for reading from the node positions ([sensing] {kind.name})")
    return kind.imperfect(np.asarray(ideal, np.float64), sensing, stream=int(recording.model.get("seed", 0)))


def kind_count(model: dict[str, Any], kind: SensorKind, sensing: SensingConfig) -> int:
    """How many signals of a kind a learner reads from a recording with this model document (0: none to read)."""
    placements = getattr(sensing, kind.name)
    return len(placements) if placements else len(model.get(kind.name, ()))
