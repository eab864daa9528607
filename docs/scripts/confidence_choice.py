"""How the calibrated confidence's features were chosen: on the corpus alone, its map fitted on the held-out
frames of every motion group but one (the frames `softarm train` fits it on: test segments, validation
recordings whole) and scored on the group left out, for each set of features (the suite is never read).

    python docs/scripts/confidence_choice.py recordings/general.pt recordings/corpus

Prints, for each set, the Spearman of the predicted IoU with the true IoU over every left-out frame, and the
AUROC of flagging the frames below IoU 0.8:

- `before the picture`: the error head's error, the surprise, the memory check and the ridge gap;
- `+ doubt`: and the decoder's doubt, its pixels' binary entropy summed;
- `+ doubt + area` (softarm's): and the decoded arm's area, its probabilities summed.
"""

import sys
from pathlib import Path

import numpy as np

from softarm.corpus.manifest import folder_recordings, motion_group
from softarm.imagine.trained import TrainedModel
from softarm.learn.dataset import split_bounds, validation_indices
from softarm.model.metrics import iou_per_frame, spearman
from softarm.trust.confidence import CalibratedTrust, calibration_features
from softarm.trust.scoring import FLAGGED, auroc

SETS = {"before the picture": 4, "+ doubt": 5, "+ doubt + area": 6}  # the first features of each set


def held_out_frames(checkpoint: str, folder: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Each corpus recording's (motion group, features (M, 6), IoU (M,)) over its held-out frames the camera saw."""
    model = TrainedModel(checkpoint, "cpu")
    paths, _ = folder_recordings(Path(folder))
    held = validation_indices(len(paths), model.config.train.validation_recordings)
    out = []
    for n, path in enumerate(paths):
        reading = model.read(path)
        rec = reading.recording
        start, end = split_bounds(len(rec.times), model.config.train)
        prediction, drawn = model.imaginer.imagine(reading.inputs)
        t = prediction.targets
        keep = (t >= (0 if n in held else start)) & (t < end) & rec.seen[t]
        features = np.column_stack(calibration_features(prediction.take(keep), True, True))
        out.append((motion_group(path), features, iou_per_frame(drawn[keep], rec.frames[t[keep]])))
    return out


def left_out_scores(frames: list[tuple[str, np.ndarray, np.ndarray]], width: int) -> tuple[float, float]:
    """Spearman and AUROC of the map on the first `width` features, each group judged by the map fitted without it."""
    predicted, truth = [], []
    for group in sorted({g for g, _, _ in frames}):
        fit = [(x[:, :width], iou) for g, x, iou in frames if g != group]
        x = np.concatenate([x for x, _ in fit])
        y = np.log(1.0 - np.concatenate([iou for _, iou in fit]) + CalibratedTrust.MARGIN)
        weights = np.linalg.lstsq(np.column_stack([x, np.ones(len(x))]), y, rcond=None)[0]
        for g, x, iou in frames:
            if g == group:
                predicted.append(np.column_stack([x[:, :width], np.ones(len(x))]) @ weights)
                truth.append(iou)
    predicted, truth = np.concatenate(predicted), np.concatenate(truth)
    return spearman(-predicted, truth), auroc(predicted, truth < FLAGGED)


def main(checkpoint: str, folder: str) -> None:
    frames = held_out_frames(checkpoint, folder)
    groups = len({g for g, _, _ in frames})
    print(f"{sum(len(iou) for _, _, iou in frames)} held-out frames of {len(frames)} recordings in {groups} groups")
    for name, width in SETS.items():
        rho, area = left_out_scores(frames, width)
        print(f"{name}: Spearman {rho:.3f}, AUROC for IoU < {FLAGGED} {area:.3f}, each group left out")


if __name__ == "__main__":
    main(*sys.argv[1:3])
