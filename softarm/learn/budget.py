"""`--minutes`: fit both networks' schedules into a wall-clock budget, from the step times measured here.

The seconds per step of each network (`step_times`, the run itself unchanged by being measured); both
schedules then shrink by one factor so that their steps, the encoding of every frame and the scoring fit what
is left of the budget. The result is written into the config as `train.max_steps_*`, so the checkpoint
records it and `--resume` continues the same schedule. Step times differ between machines: a budgeted run is not
reproducible elsewhere, an unbudgeted one is.
"""

import math

from softarm.config import override
from softarm.learn import step_times
from softarm.learn.loop import schedules
from softarm.learn.train_state import TrainState

RESERVE = 0.1  # of the budget, kept for encoding the frames and scoring held-out data


def fit_to_minutes(state: TrainState, minutes: float, spent: float) -> None:
    """Cap the schedules of `state` (not yet started) so that training ends within `minutes`, `spent`
    seconds of which are gone already (loading the data)."""
    ae, latent = schedules(state)
    precision = state.config.train.precision
    ae_step = step_times.autoencoder_steps(state, (precision,))[precision]
    latent_step = step_times.latent_steps(state, (precision,))[precision]
    budget = minutes * 60 * (1 - RESERVE) - spent
    scale = min(1.0, max(budget, 0.0) / (ae.total * ae_step + latent.total * latent_step))
    state.config = override(state.config, {"train.max_steps_ae": max(1, math.floor(ae.total * scale)),
                                           "train.max_steps_lstm": max(1, math.floor(latent.total * scale))})
