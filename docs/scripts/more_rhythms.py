"""What more rhythms of the paper's drive in the corpus would do to the surprise: the surprise fitted as `softarm
train` fits it (out of fold, the threshold with it) on the corpus's inputs plus N recordings of the paper's drive
at rhythms drawn evenly from 0.65 to 1.45 times the paper's (60 s each, nothing acting on the arm, four bands of
rhythm, each a motion group of its own), then scored on the suite as `softarm evaluate` scores it. The latent
model is the checkpoint's, trained without them: only the surprise learns from the added motion.

    python docs/scripts/more_rhythms.py recordings/general.pt recordings/corpus recordings/suite 16
"""

import copy
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
from surprise_choice import read_corpus

from softarm.config.load import config_from_dict, load_config
from softarm.imagine.trained import TrainedModel
from softarm.learn.dataset import split_bounds
from softarm.record.reader import read_model
from softarm.sim.simulate import simulate
from softarm.suite.manifest import read_suite
from softarm.suite.scoring import CaseScorer
from softarm.trust.detection import surprise_report
from softarm.trust.surprise_fit import Piece, fit_surprise

RHYTHMS = (0.65, 1.45)  # times the paper's frequencies
BANDS = 4               # motion groups the added recordings are dealt into by rhythm
SEED = 50_000           # the added recordings' first seed (the corpus's are below, the suite's from 1 000 000)


def added_pieces(model: TrainedModel, corpus: str, count: int, folder: Path) -> list[Piece]:
    """`count` recordings of the paper's drive at random rhythms, simulated as the corpus's own product recordings
    are (their configuration, without disturbances), read as the checkpoint reads them."""
    template = read_model(next(Path(corpus).glob("product_x1_*.mcap")))["config"]
    paper = np.array(load_config().excitation.frequencies)
    rhythms = np.random.default_rng(SEED).uniform(*RHYTHMS, count)
    out = []
    for i, rhythm in enumerate(rhythms):
        config = copy.deepcopy(template)
        config["run"].update(arms=1, seed=SEED + i, duration=60.0)
        config["world"]["random"] = []
        config["disturbances"] = []
        config["excitation"]["frequencies"] = list(paper * rhythm)
        path = folder / f"rhythm_{i}.mcap"
        simulate(config_from_dict(config), path)
        reading = model.read(path)
        x = model.imaginer.inputs.normalise(reading.inputs).astype(np.float32).astype(np.float64)
        a, b = split_bounds(len(x), model.config.train)
        band = min(int((rhythm - RHYTHMS[0]) / (RHYTHMS[1] - RHYTHMS[0]) * BANDS), BANDS - 1)
        out.append(Piece(x[:b], np.ones(b, bool), np.arange(b) < a, f"rhythms {band}"))
    return out


def main(checkpoint: str, corpus: str, suite: str, count: str) -> None:
    shipped, rows = read_corpus(checkpoint, corpus)
    model = TrainedModel(checkpoint, "cpu")
    pieces = [Piece(r["x"], r["calm"], r["fitting"], r["group"]) for r in rows]
    with tempfile.TemporaryDirectory() as folder:
        pieces += added_pieces(model, corpus, int(count), Path(folder))
    fitted = fit_surprise(pieces, shipped.felt, shipped.command, model.config.integration.frame_dt,
                          model.config.train.false_alarms_per_minute)
    model.imaginer = replace(model.imaginer, surprise=replace(fitted, memory=shipped.memory))
    scorer = CaseScorer(model)  # each case's surprise exactly as `softarm evaluate` scores it
    cases = [scorer.score(case, None)[2] for case in read_suite(suite).cases]
    report = surprise_report(cases, fitted.threshold, model.config.integration.frame_dt)
    crying = {family: rate for family, rate in report["false_alarms_per_minute_by_family"].items() if rate > 0}
    print(f"{count} added: threshold {fitted.threshold:.1f}; false alarms a minute: "
          f"{', '.join(f'{f} {r:.2f}' for f, r in crying.items()) or 'none on any undisturbed family'}; "
          f"the suite's calm threshold {report['thresholds']['suite']:.1f}")
    for kind, row in report["families"].items():
        print(f"  {kind}: AUROC {row['auroc']:.3f}, alarmed {row['detected_own']:.0%} "
              f"(median {row['latency_ms_own']:.0f} ms), at the suite's calm threshold {row['detected_suite']:.0%}")


if __name__ == "__main__":
    main(*sys.argv[1:5])
