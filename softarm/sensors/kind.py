"""What every recorded sensor kind declares, so that the config, the recording (channel, schema, metadata), the
reader and the model's input channel handle it alike without naming it."""

from typing import Any, ClassVar, Sequence

import numpy as np


class SensorKind:
    name: ClassVar[str]      # config key under [sensors] and [sensing], model-document key, input channel name
    topic: ClassVar[str]     # its recorded channel
    field: ClassVar[str]     # the JSON field holding one reading per sensor
    unit: ClassVar[str]      # SI unit of a reading
    width: ClassVar[int]     # nodes one sensor is placed on
    title: ClassVar[str]     # the channel's schema title
    description: ClassVar[str]  # what one reading is, for the schema

    def check(self, placements: Sequence[Sequence[int]], nodes: int, key: str) -> np.ndarray:
        """The placements as an int array, refusing one no arm of `nodes` nodes can carry (a `softarm` error
        naming `key`)."""
        raise NotImplementedError

    def ideal(self, positions: np.ndarray, rest: np.ndarray, placements: np.ndarray) -> np.ndarray:
        """(..., S) ideal readings for positions (..., N, 2) m of an arm whose rest positions are (N, 2)."""
        raise NotImplementedError

    def imperfect(self, ideal: np.ndarray, sensing: Any, stream: int) -> np.ndarray:
        """The readings a learner gets under `sensing`'s imperfections for this kind, seeded by `stream`."""
        raise NotImplementedError
