"""Why pushes go unalarmed: each push of a suite with the highest surprise it raised while it acted, beside the
lowest threshold at which each undisturbed family alone starts at most one false alarm a minute. No threshold
below the largest of those keeps every family calm, so the pushes that peak under it cannot be alarmed by any
choice of threshold, only by a surprise that stays lower on motion the corpus does not hold.

    python docs/scripts/push_peaks.py recordings/general.pt recordings/suite
"""

import sys

import numpy as np

from softarm.imagine.trained import TrainedModel
from softarm.suite.manifest import read_suite
from softarm.trust.alarm import alarm_threshold
from softarm.trust.detection import PER_MINUTE


def main(checkpoint: str, folder: str) -> None:
    model, suite = TrainedModel(checkpoint, "cpu"), read_suite(folder)
    frame_dt = model.config.integration.frame_dt
    pushes, calm, shipped = [], {}, float("nan")
    for case in suite.cases:
        kind = "motion" if suite.groups[case.family] == "motion" else case.family
        if kind not in ("motion", "push"):
            continue
        reading = model.read(case.path, case.sensing)
        imaginer = model.imaginer_for(reading.config)
        _, targets = imaginer.windows(reading.inputs)
        surprise = imaginer.predict(reading.inputs).surprise
        shipped = imaginer.surprise.threshold
        if kind == "motion":
            calm.setdefault(case.family, []).append((surprise, np.ones(len(surprise), bool)))
            continue
        times = reading.recording.times[targets]
        for push in reading.recording.model["disturbances"]:
            start, end = np.searchsorted(times, [push["start"] - 1e-9, push["end"] - 1e-9])
            pushes.append((float(np.hypot(*push["force"])) * 1e3, (push["end"] - push["start"]) * 1e3,
                           push["nodes"][0], float(np.nanmax(surprise[start:end]))))
    limits = {family: alarm_threshold(series, frame_dt, PER_MINUTE) for family, series in calm.items()}
    strictest = max(limits, key=limits.get)
    print("| undisturbed family | threshold for at most one false alarm a minute |\n|---|---:|")
    for family, limit in sorted(limits.items(), key=lambda item: -item[1]):
        print(f"| `{family}` | {limit:.1f} |")
    print("\n| force (mN a node) | duration (ms) | first node | highest surprise while it acts |\n|---:|---:|---:|---:|")
    for force, duration, node, peak in sorted(pushes):
        print(f"| {force:.0f} | {duration:.0f} | {node} | {peak:.1f} |")
    above = sum(peak > limits[strictest] for *_, peak in pushes)
    print(f"\nabove {limits[strictest]:.1f} (`{strictest}`): {above} of {len(pushes)} pushes; the checkpoint's "
          f"threshold {shipped:.1f}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
