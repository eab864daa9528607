"""What a push leaves on the stretch, whatever reads it: each push recording of a suite simulated again with its
pushes' forces set to zero (the same seed, drive and step), so the difference between the two is the push's own
imprint (simulated again with its pushes, a recording must give its own stretch bit for bit, or the script says so
and stops). Beside each push: that imprint at its largest while the push acts and in the 200 ms after, in units of
each sensor's residual spread (the forward model's out-of-fold error on undisturbed motion, the checkpoint's `scale`);
the part of it no straight line through the two samples before foresees (its second difference), what a one-step
prediction is left with; and the checkpoint's surprise in that window with the push and without it.

    python docs/scripts/push_imprint.py recordings/general.pt recordings/suite
"""

import copy
import sys
import tempfile
from pathlib import Path

import numpy as np

from softarm.config.load import config_from_dict
from softarm.imagine.trained import TrainedModel
from softarm.record.reader import read_recording
from softarm.record.recording import Recording
from softarm.sim.simulate import simulate
from softarm.suite.manifest import read_suite

AFTER = 20  # imagined frames after a push's end that still count as its window (200 ms at the default rate)


def simulated_again(path: Path, out: Path, pushes: bool) -> Path:
    """The recording at `path` simulated again from its own metadata into `out`, its pushes as drawn or with every
    push's force zero."""
    model = read_recording(path, nodes=False).model
    config = copy.deepcopy(model["config"])
    config["run"].update(arms=1, seed=int(model["seed"]))
    config["world"]["random"] = []  # what was drawn is stated below, as the recording's metadata holds it
    config["disturbances"] = [d if pushes else {**d, "force": [0.0, 0.0]} for d in model["disturbances"]]
    simulate(config_from_dict(config), out)
    return out


def main(checkpoint: str, folder: str) -> None:
    model, suite = TrainedModel(checkpoint, "cpu"), read_suite(folder)
    scale, felt = model.imaginer.surprise.scale, list(model.imaginer.surprise.felt)

    def read(path: Path, sensing: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray, Recording]:
        """The normalised felt stretch, the surprise and the times at the imagined frames, and the recording."""
        reading = model.read(path, sensing)
        imaginer = model.imaginer_for(reading.config)
        _, targets = imaginer.windows(reading.inputs)
        return (imaginer.inputs.normalise(reading.inputs)[:, felt], imaginer.predict(reading.inputs).surprise,
                reading.recording.times[targets], reading.recording)

    rows = []
    with tempfile.TemporaryDirectory() as calm_folder:
        for case in (c for c in suite.cases if c.family == "push"):
            pushed, surprise, times, recording = read(case.path, case.sensing)
            again = simulated_again(case.path, Path(calm_folder) / f"again_{case.path.name}", True)
            if not np.array_equal(read_recording(again, nodes=False).stretch, recording.stretch):
                raise SystemExit(f"{case.path.name} simulated again from its metadata differs: no imprint to measure")
            calm, calm_surprise, _, _ = read(simulated_again(case.path, Path(calm_folder) / case.path.name, False),
                                             case.sensing)
            imprint = (pushed - calm) / scale
            unforeseen = np.full_like(imprint, np.nan)
            unforeseen[2:] = imprint[2:] - 2 * imprint[1:-1] + imprint[:-2]
            for push in recording.model["disturbances"]:
                start, end = np.searchsorted(times, [push["start"] - 1e-9, push["end"] - 1e-9])
                window = slice(start, end + AFTER)
                rms = [float(np.sqrt(np.nanmax((x[window] ** 2).mean(axis=1)))) for x in (imprint, unforeseen)]
                rows.append((float(np.hypot(*push["force"])) * 1e3, (push["end"] - push["start"]) * 1e3,
                             push["nodes"][0], *rms, float(np.nanmax(surprise[window])),
                             float(np.nanmax(calm_surprise[window]))))
    print("| push: force (mN a node), duration (ms), first node | imprint, largest (spreads) | its unforeseen step "
          "| surprise | surprise, no push |")
    print("|---|---:|---:|---:|---:|")
    for force, duration, node, imprint, step, peak, calm_peak in sorted(rows):
        print(f"| {force:.0f}, {duration:.0f}, {node} | {imprint:.1f} | {step:.2f} | {peak:.1f} | {calm_peak:.1f} |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
