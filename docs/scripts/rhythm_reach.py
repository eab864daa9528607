"""How far each predictor of the next stretch sample reaches across the rhythms of the paper's drive: the surprise's
forward model (the last 10 samples of every channel) and the memory check (the latent model's recurrent state),
each one's mean squared residual in units of its own spread, over the undisturbed samples from 1 s on. The
corpus's `product_x*` groups are the rhythms both were fitted on (a band's arms each at a rhythm of its own, shown as
the band); the suite's `paper_frequency` plays the same drive at 0.8 and 1.25 times the paper's rhythm.

    python docs/scripts/rhythm_reach.py recordings/general.pt recordings/corpus recordings/suite
"""

import sys
from pathlib import Path
from typing import Optional

import numpy as np

from softarm.config.load import load_config
from softarm.corpus.manifest import folder_recordings, motion_group
from softarm.imagine.trained import TrainedModel
from softarm.suite.manifest import read_suite

SETTLED = 100  # samples: the first second is left out (the surprise is silent before sample 74)


def main(checkpoint: str, corpus: str, suite: str) -> None:
    model = TrainedModel(checkpoint, "cpu")
    imaginer = model.imaginer
    surprise = imaginer.surprise
    paper = load_config().excitation.frequencies[0]  # the paper's drive: the defaults'

    def errors(path: Path, sensing: Optional[dict] = None) -> Optional[tuple[str, float, float]]:
        """The drive's rhythm (its first frequency over the paper's, or the corpus group's band) and the two mean
        squared residuals; None where nothing is undisturbed after the first second (a load from the start)."""
        reading = model.read(path, sensing) if sensing is not None else model.read(path)
        read = imaginer.inputs.normalise(reading.inputs).astype(np.float32)  # as the model reads them
        inputs = read.astype(np.float64)
        memory = surprise.memory.residuals(imaginer.latent.states(read), inputs)
        forward = (surprise.residuals(inputs) ** 2).mean(axis=1)
        active = reading.recording.active
        calm = ~active.any(axis=1) if active.size else np.ones(len(inputs), bool)
        keep = calm & (np.arange(len(inputs)) >= SETTLED)
        group = motion_group(path).removeprefix("product_")
        rhythm = group if "-" in group else f"x{reading.recording.model['excitation']['frequencies'][0] / paper:.3g}"
        return (rhythm, float(np.nanmean(forward[keep])), float(np.nanmean(memory[keep]))) if keep.any() else None

    rows: dict[tuple[str, str], list[tuple[float, float]]] = {}
    paths, _ = folder_recordings(Path(corpus))
    read = [(errors(p), "corpus") for p in paths if motion_group(p).startswith("product_")]
    read += [(errors(c.path, c.sensing), "suite") for c in read_suite(suite).cases if c.family == "paper_frequency"]
    for (rhythm, forward, memory), source in ((row, source) for row, source in read if row is not None):
        rows.setdefault((rhythm, source), []).append((forward, memory))
    print("| the paper's drive, rhythm | recordings | forward model | memory check |\n|---|---|---:|---:|")
    for (rhythm, source), values in sorted(rows.items(), key=lambda row: float(row[0][0][1:].split("-")[0])):
        forward, memory = np.mean(values, axis=0)
        print(f"| {rhythm} | {len(values)} of the {source} | {forward:.3f} | {memory:.2f} |")


if __name__ == "__main__":
    main(*sys.argv[1:4])
