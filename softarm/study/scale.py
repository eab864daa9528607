"""How big a study runs: the shared corpus, the training schedule and the suite every trial is scored on.

Training is capped in steps, not minutes, so every trial of a study gets the same optimisation whatever
else the machine (or another cluster node) is doing, and a rerun elsewhere trains the same.
"""

from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class Scale:
    name: str                    # recorded with every trial: a trial run at another scale is not reused
    preset: str                  # of the shared corpus (softarm.corpus.presets)
    arms: int
    duration: float              # s per arm
    train: dict[str, Any] = field(default_factory=dict)  # config overrides beneath every trial's own
    first_recording_only: bool = False  # score on one recording per suite level (half the frames)
    quick_trials: bool = False   # run only the study's quick subset of trials


# Two fifths of the default corpus and about a third of the default schedule: a trial takes some 4 to 5 minutes on
# one core here, so the 19 trials of `sensors` (15 stretch, 4 bend) take some 40 minutes on this 2-core machine.
FULL = Scale("full", "general", 32, 60.0, {"train.max_steps_ae": 2000, "train.max_steps_lstm": 6000})
QUICK = Scale("quick", "general", 19, 20.0, {"train.max_steps_ae": 300, "train.max_steps_lstm": 1000},
              first_recording_only=True, quick_trials=True)
