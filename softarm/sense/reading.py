"""What a learner reads from a recording: the stretch of the configured pairs with the configured
imperfections, one realisation per recording (its simulation seed is the noise stream).

Training, replay and evaluation all read through `sensed_stretch`, so a checkpoint imagines from
exactly the kind of signal it was trained on, unless a caller asks for another sensor model.
"""

from typing import TYPE_CHECKING, Any

import numpy as np

from softarm.config import SensingConfig
from softarm.sense.imperfections import SensorModel
from softarm.sense.pairs import recording_stretch

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
