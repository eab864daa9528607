"""Sensor kinds: what a sensor reads from the arm's state, where it sits, its recorded channel and its imperfections,
one class each (`kind.SensorKind`), listed here by the name the config, the recording's metadata and the model's
input channel use. A new kind is one module and one line of KINDS.
"""

from softarm.sensors.bend import Bend
from softarm.sensors.kind import SensorKind

KINDS: dict[str, type[SensorKind]] = {"bend": Bend}  # the stretch is recorded by the frame encoder (/arm/stretch)

__all__ = ["KINDS", "SensorKind", "declared"]


def declared(placements: dict[str, object]) -> list[SensorKind]:
    """The kinds a model document (or a config section) places: each kind whose key it holds, non-empty."""
    return [cls() for name, cls in KINDS.items() if placements.get(name)]
