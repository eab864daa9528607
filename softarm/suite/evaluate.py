"""`softarm evaluate`: a checkpoint's imagination on every family of the suite, beside the trivial answers.

Per family, over every imagined frame of its recordings: IoU, BCE and tip error of the model, of the
mean training frame, of the ridge map from the same input windows (both fitted at training time
and kept in the checkpoint) and of the AE ceiling (decode the true frame's own code: the best any
latent predictor can do). Skill = (IoU - IoU_mean) / (IoU_ceiling - IoU_mean): the share of the
reachable gain above the trivial answer, which raw IoU hides where the arm hardly moves. Over every
frame of the suite, the confidence figures say how well the model's own trust ranks its frames.
"""

from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Optional, Union

import numpy as np

from softarm.suite.manifest import SuiteCase, read_suite

if TYPE_CHECKING:
    from softarm.model.trained import TrainedModel

LEAST_TRUSTED = 0.1  # share of frames whose IoU the confidence figures single out
Progress = Callable[[int, int], None]


def evaluate_suite(checkpoint: Union[str, Path], folder: Union[str, Path],
                   sensor_noise: Optional[dict[str, Any]] = None, progress: Optional[Progress] = None) -> dict[str, Any]:
    """The evaluation document: {"suite", "checkpoint", "families": {name: scores, ...}, "mean": scores}.

    Each level is read with the imperfections the suite gives it, over those the checkpoint was trained
    with; `sensor_noise` replaces both for every level.
    """
    from softarm.model.trained import TrainedModel  # torch loads here, not when softarm is imported

    suite = read_suite(folder)
    scorer = CaseScorer(TrainedModel(checkpoint))
    per_family: dict[str, dict[str, list[dict[str, np.ndarray]]]] = {f: {} for f in suite.families}
    confidence, iou = [], []
    for done, case in enumerate(suite.cases, 1):
        scores, trust = scorer.score(case, sensor_noise)
        for answer, answer_scores in scores.items():
            per_family[case.family].setdefault(answer, []).append(answer_scores)
        confidence.append(trust)
        iou.append(scores["model"]["iou"])
        if progress:
            progress(done, len(suite.cases))
    families = {name: family_scores(parts) for name, parts in per_family.items()}
    groups = {group: {f: families[f] for f in families if suite.groups[f] == group}
              for group in dict.fromkeys(suite.groups.values())}
    return {"suite": suite.version, "checkpoint": str(checkpoint), "families": families,
            "mean": mean_over_families(families),
            "group_means": {group: mean_over_families(rows) for group, rows in groups.items()},
            "confidence": confidence_scores(np.concatenate(confidence), np.concatenate(iou)),
            "probes": suite.probes, "groups": suite.groups}


class CaseScorer:
    """One trained model scoring recording after recording."""

    def __init__(self, model: "TrainedModel"):
        self.model = model

    def score(self, case: SuiteCase, sensor_noise: Optional[dict[str, Any]]
              ) -> tuple[dict[str, dict[str, np.ndarray]], np.ndarray]:
        """Per-frame scores of every answer on one recording, and the model's confidence in each frame."""
        from softarm.model.answers import PRIVILEGED, score_answers, score_node_ridge
        from softarm.model.autoencoder import encode_frames

        reading = self.model.read(case.path, sensor_noise if sensor_noise is not None else case.sensing)
        imaginer = self.model.imaginer
        windows, targets = imaginer.windows(reading.inputs)
        truth = reading.recording.frames[targets]
        ceiling = imaginer.latent_scaler.forward(encode_frames(imaginer.autoencoder, truth))
        prediction = imaginer.predict(reading.inputs)
        rec, baselines = reading.recording, self.model.baselines
        scores = score_answers(imaginer, baselines, truth, prediction.latents, windows, ceiling, rec.pixels_per_metre)
        if baselines.nodes is not None:
            scores[PRIVILEGED] = score_node_ridge(imaginer, baselines, reading.inputs, targets, truth, rec.model,
                                                  rec.pixels_per_metre)
        return scores, prediction.confidence


def family_scores(parts: dict[str, list[dict[str, np.ndarray]]]) -> dict[str, Any]:
    """One family's row: the model's means and skill, the frame count, and every baseline's means."""
    from softarm.model.metrics import summarise

    means = {answer: summarise({k: np.concatenate([p[k] for p in scores]) for k in scores[0]})
             for answer, scores in parts.items()}
    row = {key: means["model"][key] for key in ("iou", "bce")}
    row["tip_error_mm"] = means["model"]["tip_mm"]
    row["tip_error_median_mm"] = float(np.nanmedian(np.concatenate([p["tip_mm"] for p in parts["model"]])))
    row["skill"] = skill(means["model"]["iou"], means["mean_frame"]["iou"], means["ae_ceiling"]["iou"])
    row["frames"] = int(sum(len(p["iou"]) for p in parts["model"]))
    row["baselines"] = {answer: {"iou": means[answer]["iou"], "bce": means[answer]["bce"],
                                 "tip_error_mm": means[answer]["tip_mm"]} for answer in parts if answer != "model"}
    row["baselines"]["ridge"]["skill"] = skill(means["ridge"]["iou"], means["mean_frame"]["iou"],
                                               means["ae_ceiling"]["iou"])
    return row


def confidence_scores(confidence: np.ndarray, iou: np.ndarray) -> dict[str, float]:
    """How well the confidence ranks imagined frames by their true IoU, over every frame of the suite: the
    Spearman correlation, and the mean IoU of the least-trusted LEAST_TRUSTED of frames against the rest's."""
    from softarm.model.metrics import spearman

    order = np.argsort(confidence, kind="stable")
    low = order[:max(1, round(len(order) * LEAST_TRUSTED))]
    rest = np.ones(len(order), bool)
    rest[low] = False
    return {"spearman": spearman(confidence, iou), "least_trusted_iou": float(iou[low].mean()),
            "rest_iou": float(iou[rest].mean()) if rest.any() else float("nan"), "least_trusted_share": LEAST_TRUSTED,
            "frames": int(len(iou))}


def skill(iou: float, floor: float, ceiling: float) -> float:
    """Share of the gain from the mean frame to the AE ceiling that an answer reaches (1: all of it)."""
    return (iou - floor) / (ceiling - floor) if ceiling > floor else float("nan")


def mean_over_families(families: dict[str, dict[str, Any]]) -> dict[str, float]:
    """Every family weighs the same, whatever its frame count."""
    keys = ("iou", "bce", "tip_error_mm", "tip_error_median_mm", "skill")
    return {key: float(np.nanmean([row[key] for row in families.values()])) for key in keys}
