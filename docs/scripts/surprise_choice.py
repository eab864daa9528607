"""How the surprise was chosen: on the corpus alone, every motion group judged by a forward model fitted without
it (the groups dealt into blocks as softarm deals them), four forward models and spread maps side by side, and
the last with the innovation beside its error (the suite is never read).

    python docs/scripts/surprise_choice.py recordings/general.pt recordings/corpus

- `linear`: the lagged linear map, the spread from the arm's vigour alone;
- `linear + novelty`: the same map, the spread from its vigour and the motion's novelty;
- `products + novelty`: the map with the products of the newest sample and its difference;
- `products + novelty + correction`: and a network fitted to what that map leaves;
- `... + innovation` (softarm's): the surprise averages the error with what the last errors did not foresee of it.

Each prints the threshold set out of fold for one false alarm a minute and the false alarms it gives, the AUROC
of the surprise against the frames each kind of disturbance acts in (an obstacle while the arm touches it), the
frames of the corpus where no disturbance is active the negatives (as the fit counts them: an obstacle standing
is active), and the share of disturbances alarmed at that threshold.
"""

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from softarm.corpus.manifest import folder_recordings, motion_group
from softarm.imagine.trained import TrainedModel
from softarm.learn.dataset import split_bounds, validation_indices
from softarm.record.reader import Recording
from softarm.trust.alarm import alarm_onsets, alarm_threshold, runs
from softarm.trust.correction import fit_correction
from softarm.trust.scoring import auroc
from softarm.trust.surprise import LAGS, SurpriseModel, feature_width, linear_width, told
from softarm.trust.surprise_fit import BLOCKS, RIDGE, _quiet, _ridge, _spread_map, _spreads, fit_innovation

KINDS = ("push", "payload", "stiffness", "obstacle")


def acting(rec: Recording) -> np.ndarray:
    """(T, D) each disturbance acting at each frame: an obstacle while the arm touches it."""
    out = rec.active.copy()
    obstacle = [d["kind"] == "obstacle" for d in rec.model.get("disturbances", [])]
    if rec.touching is not None:
        out[:, obstacle] = rec.touching[:, obstacle]
    return out


def read_corpus(checkpoint: str, folder: str) -> tuple[SurpriseModel, list[dict]]:
    model = TrainedModel(checkpoint, "cpu")
    surprise, inputs, train = model.imaginer.surprise, model.imaginer.inputs, model.config.train
    paths, _ = folder_recordings(Path(folder))
    held = validation_indices(len(paths), train.validation_recordings)
    out = []
    for n, path in enumerate(paths):
        reading = model.read(path)
        rec = reading.recording
        x = inputs.normalise(reading.inputs).astype(np.float32).astype(np.float64)
        a, b = split_bounds(len(x), train)
        kinds = [d["kind"] for d in rec.model.get("disturbances", [])]
        out.append({"x": x[:b], "calm": ~rec.active.any(axis=1)[:b], "acting": acting(rec)[:b], "kinds": kinds,
                    "fitting": np.arange(b) < (0 if n in held else a), "group": motion_group(path)})
    return surprise, out


def judged(surprise: SurpriseModel, corpus: list[dict], products: bool, novelty: bool, corrected: bool
           ) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Each recording's residuals (T, P) and spread map inputs (T, DESIGN or one fewer without the novelty), out
    of fold (the motion groups dealt into blocks as softarm deals them)."""
    channels, commands = corpus[0]["x"].shape[1], len(surprise.command)
    linear = linear_width(channels, commands)
    columns = np.r_[np.arange(feature_width(channels, commands) - 1 if products else linear),
                    feature_width(channels, commands) - 1]
    probe = SurpriseModel(np.zeros((feature_width(channels, commands), 1)), np.ones(1), np.zeros(8),
                          np.eye(linear + 1), 0.0, surprise.felt, surprise.command)
    rows = [(probe.features(c["x"])[:, columns], c["x"][LAGS:, list(surprise.felt)],
             _quiet(c["calm"]) & c["fitting"][LAGS:]) for c in corpus]
    residuals, designs = [None] * len(corpus), [None] * len(corpus)
    groups = sorted({c["group"] for c in corpus})
    for block in (groups[i::BLOCKS] for i in range(min(BLOCKS, len(groups)))):
        others = [r for r, c in zip(rows, corpus) if c["group"] not in block]
        weights = _ridge(others, RIDGE, unshrunk=-1)
        if corrected:
            x = np.concatenate([x[k & np.isfinite(y).all(axis=1)] for x, y, k in others])
            y = np.concatenate([y[k & np.isfinite(y).all(axis=1)] for _, y, k in others])
            correction = fit_correction(x[:, :linear], y - x @ weights)
        lin = np.r_[np.arange(linear), len(columns) - 1]
        moment = sum(x[k][:, lin].T @ x[k][:, lin] for x, _, k in others) / sum(k.sum() for _, _, k in others)
        precision = np.linalg.inv(moment + 1e-6 * np.trace(moment) / len(lin) * np.eye(len(lin)))
        judge = SurpriseModel(np.zeros((feature_width(channels, commands), 1)), np.ones(1), np.zeros(8), precision,
                              0.0, surprise.felt, surprise.command)
        for n, c in enumerate(corpus):
            if c["group"] in block:
                x, y, _ = rows[n]
                predicted = x @ weights + (correction(x[:, :linear]) if corrected else 0.0)
                residuals[n] = np.vstack([np.full((LAGS, y.shape[1]), np.nan), y - predicted])
                design = judge.design(c["x"])
                designs[n] = design if novelty else np.delete(design, -2, axis=1)
    return residuals, designs


def surprises(surprise: SurpriseModel, corpus: list[dict], residuals: list[np.ndarray], designs: list[np.ndarray],
              innovated: bool) -> list[np.ndarray]:
    """Each recording's surprise from its out-of-fold residuals, as softarm fits it (`fit_surprise`), with or
    without the innovation; the threshold appended last."""
    quiet = [_quiet(c["calm"], pad=True) for c in corpus]
    scale = _spreads(residuals, quiet)
    errors = [r / scale for r in residuals]
    spread = _spread_map(designs, [(e ** 2).mean(axis=1) for e in errors], quiet)
    innovation = (fit_innovation([e / np.sqrt(np.exp(d @ spread))[:, None] for e, d in zip(errors, designs)],
                                 designs, quiet) if innovated else None)
    judge = replace(surprise, spread=spread, innovation=innovation)
    series = [told(judge.values(e, d, np.zeros_like(e))[0]) for e, d in zip(errors, designs)]
    return [*series, alarm_threshold([(s, c["calm"]) for s, c in zip(series, corpus)], 0.01, 1.0)]


def scores(series: list[np.ndarray], threshold: float, corpus: list[dict]) -> str:
    negatives = np.concatenate([s[c["calm"]] for s, c in zip(series, corpus)])
    minutes = np.isfinite(negatives).sum() * 0.01 / 60
    false = sum(int(c["calm"][alarm_onsets(s, threshold)].sum()) for s, c in zip(series, corpus))  # started in calm
    out = [f"false alarms {false / minutes:.2f}/min"]
    for kind in KINDS:
        positives, found = [], []
        for s, c in zip(series, corpus):
            for d in (d for d, k in enumerate(c["kinds"]) if k == kind):
                positives.append(s[c["acting"][:, d]])
                found += [bool((np.nan_to_num(s[a:b]) > threshold).any()) for a, b in runs(c["acting"][:, d])]
        score = np.concatenate([*positives, negatives])
        label = np.r_[np.ones(sum(map(len, positives)), bool), np.zeros(len(negatives), bool)]
        finite = np.isfinite(score)
        out.append(f"{kind} {auroc(score[finite], label[finite]):.3f} ({np.mean(found):.0%})")
    return ", ".join(out)


def main(checkpoint: str, folder: str) -> None:
    surprise, corpus = read_corpus(checkpoint, folder)
    for name, products, novelty, corrected in (("linear", False, False, False),
                                               ("linear + novelty", False, True, False),
                                               ("products + novelty", True, True, False),
                                               ("products + novelty + correction", True, True, True)):
        residuals, designs = judged(surprise, corpus, products, novelty, corrected)
        for innovated in (False, True) if corrected else (False,):
            *series, threshold = surprises(surprise, corpus, residuals, designs, innovated)
            label = f"{name} + innovation" if innovated else name
            print(f"{label}: threshold {threshold:.1f}, {scores(series, threshold, corpus)}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
