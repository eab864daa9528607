"""The trust's fits fed from the training: what `softarm.trust` fits (the surprise's forward model and memory
check, the calibrated confidence's map) gathered from the training's recordings and networks.

The surprise: the training segments of every recording fit its forward model, every motion group judged by the
one fitted without it calibrates the rest. The calibrated confidence: on held-out frames, each recording
imagined from its first sample as replay would, the frames' true IoU against what the model knows without a
camera.
"""

from dataclasses import replace
from typing import Any, Optional, Sequence

import numpy as np

from softarm.learn.dataset import RunData
from softarm.learn.evaluate import evenly, imaginer_of
from softarm.learn.train_state import TrainState
from softarm.model.metrics import iou_per_frame
from softarm.model.prediction import Prediction
from softarm.trust.confidence import fit_calibrated
from softarm.trust.surprise import LAGS, SurpriseModel
from softarm.trust.surprise_fit import Piece, fit_memory_check, fit_surprise

MAX_FRAMES = 20_000  # held-out frames the map is fitted on, evenly spread


def fit_calibration(state: TrainState) -> dict[str, Any]:
    """The calibrated confidence's map (`fit_calibrated`) on the held-out frames, the gap to the ridge baseline's
    latent among its features (the baselines are fitted first)."""
    imaginer, data = imaginer_of(state), state.data
    parts, where = [], []
    for n, (seq, prediction) in enumerate(zip(data.sequences,
                                              imaginer.predict_many([s.inputs for s in data.sequences]))):
        start, end = seq.segment("test")
        keep = (prediction.targets >= start) & (prediction.targets < end)
        if seq.seen is not None:
            keep &= seq.seen[prediction.targets]
        parts.append(prediction.take(keep))
        where.append(np.stack([np.full(int(keep.sum()), n), parts[-1].targets], axis=1))
    picked = evenly(sum(len(w) for w in where), MAX_FRAMES)
    held_out, where = Prediction.join(parts).take(picked), np.concatenate(where)[picked]
    drawn = imaginer.decode(held_out.latents)
    return fit_calibrated(held_out.with_picture(drawn), iou_per_frame(drawn, data.target_frames(where)))


def fit_surprise_of(state: TrainState) -> Optional[SurpriseModel]:
    """None when the model reads no sensor (nothing felt to be surprised by) or the recordings hold too little
    undisturbed motion to judge any of it out of fold (a disturbance acting throughout). The surprise reads each
    recording up to its imagination segment (kept for scoring the imagination), its forward model fits on the
    training segments, and each motion fold is judged out of fold (`surprise_folds`). The memory check fits on
    the training segments and takes its spreads from the held-out motion (test segments, validation
    recordings)."""
    data, t = state.data, state.config.train
    columns = np.cumsum([0, *data.widths])
    felt = [c for ch, a, b in zip(data.channels, columns, columns[1:]) if ch.felt for c in range(a, b)]
    command = [c for c in range(columns[-1]) if c not in felt]
    if not felt:
        return None
    pieces, fitting, calibration = [], [], []
    for seq, fold in zip(data.sequences, surprise_folds(data.sequences)):
        read = state.inputs.normalise(seq.inputs).astype(np.float32)  # as the model reads them
        states, inputs = state.latent.states(read), read.astype(np.float64)
        calm = seq.calm if seq.calm is not None else np.ones(len(inputs), bool)
        end = seq.segment("test")[1]
        trains = np.arange(end) < seq.segment("train")[1]
        if len(data.sequences) > 1:
            pieces.append(Piece(inputs[:end], calm[:end], trains, fold))
        else:  # a lone recording: its folds are stretches of it in time
            edges = [end * i // BLOCKS for i in range(BLOCKS + 1)]
            pieces.extend(Piece(inputs[s:e], calm[s:e], trains[s:e], f"{fold}, stretch {i}")
                          for i, (s, e) in enumerate(zip(edges, edges[1:])))
        for segment, into in (("train", fitting), ("test", calibration)):
            a, b = seq.segment(segment)
            if b - a > LAGS + 1:
                into.append((states[a:b], inputs[a:b], calm[a:b]))
    model = fit_surprise(pieces, felt, command, float(np.median(np.diff(data.sequences[0].times))),
                         t.false_alarms_per_minute, str(state.device))
    if model is None:
        return None
    return replace(model, memory=fit_memory_check(fitting, felt, command, calibration or fitting))


BLOCKS = 4  # a lone recording's folds: this many stretches of it in time


def surprise_folds(sequences: Sequence[RunData]) -> list[str]:
    """Each recording's fold: its corpus's motion group where the corpus names two or more, else its own."""
    groups = [s.group for s in sequences]
    if len(set(groups)) > 1 and all(groups):
        return groups
    return [f"recording {i}" for i in range(len(sequences))]
