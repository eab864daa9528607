"""The surprise's forward model, fitted once the latent model is trained (docs/model.md, Surprise).

It reads the main latent model's recurrent states over every recording: the training segments fit the
forward model, the held-out motion (the test segments, validation recordings whole) sets each sensor's
residual spread and the alarm's threshold. Frames where a disturbance acts are left out of both: the model
learns what undisturbed motion feels like.
"""

from typing import Optional

import numpy as np
import torch

from softarm.learn.train_state import TrainState
from softarm.model.surprise import SurpriseModel, fit_surprise


@torch.inference_mode()
def fit_surprise_of(state: TrainState) -> Optional[SurpriseModel]:
    """None when the model reads no stretch (nothing felt to be surprised by)."""
    data, t = state.data, state.config.train
    columns = np.cumsum([0, *data.widths])
    felt = [c for ch, a, b in zip(data.channels, columns, columns[1:]) if ch.name == "stretch" for c in range(a, b)]
    command = [c for c in range(columns[-1]) if c not in felt]
    if not felt:
        return None
    fitting, calibration = [], []
    for seq in data.sequences:
        inputs = state.inputs.normalise(seq.inputs)
        states = state.latent.states(inputs.astype(np.float32))
        calm = seq.calm if seq.calm is not None else np.ones(len(inputs), bool)
        for segment, into in (("train", fitting), ("test", calibration)):
            a, b = seq.segment(segment)
            if b - a > 1:
                into.append((states[a:b], inputs[a:b], calm[a:b]))
    return fit_surprise(fitting, felt, command, calibration or fitting, float(np.median(np.diff(data.sequences[0].times))),
                        t.false_alarms_per_minute)
