"""The surprise's spread family by family on a suite: the median, 99th percentile and largest surprise over each
family's imagined frames, each recording read with its level's imperfections, as `softarm evaluate` reads it.

    python docs/scripts/surprise_spread.py recordings/general.pt recordings/suite
"""

import sys

import numpy as np

from softarm.imagine.trained import TrainedModel
from softarm.suite.manifest import read_suite


def main(checkpoint: str, folder: str) -> None:
    model, suite = TrainedModel(checkpoint, "cpu"), read_suite(folder)
    felt: dict[str, list[np.ndarray]] = {family: [] for family in suite.families}
    for case in suite.cases:
        reading = model.read(case.path, case.sensing)
        surprise = model.imaginer_for(reading.config).predict(reading.inputs).surprise
        felt[case.family].append(surprise[np.isfinite(surprise)])
    print("| family | kind | median | 99th percentile | largest |\n|---|---|---:|---:|---:|")
    for family, parts in felt.items():
        values = np.concatenate(parts)
        kind = "undisturbed" if suite.groups[family] == "motion" else "disturbed"
        print(f"| `{family}` | {kind} | {np.median(values):.1f} | {np.percentile(values, 99):.1f} | {values.max():.1f} |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
