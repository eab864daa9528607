"""`softarm evaluate`: a checkpoint's imagination on every family of the suite, beside the trivial answers.

Per family, over every imagined frame of its recordings: IoU, BCE and tip error of the model, of the
mean training frame, of the ridge map from the same stretch windows (both fitted at training time
and kept in the checkpoint) and of the AE ceiling (decode the true frame's own code: the best any
latent predictor can do). Skill = (IoU - IoU_mean) / (IoU_ceiling - IoU_mean): the share of the
reachable gain above the trivial answer, which raw IoU hides where the arm hardly moves. Over every
frame of the suite, the confidence figures say how well the model's own trust ranks its frames.
"""

from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np

from softarm.suite.manifest import SuiteCase, read_suite

ANSWERS = ("model", "mean_frame", "ridge", "ae_ceiling")
LEAST_TRUSTED = 0.1  # share of frames whose IoU the confidence figures single out
Progress = Callable[[int, int], None]


def evaluate_suite(checkpoint: Union[str, Path], folder: Union[str, Path],
                   sensor_noise: Optional[dict[str, Any]] = None, progress: Optional[Progress] = None) -> dict[str, Any]:
    """The evaluation document: {"suite", "checkpoint", "families": {name: scores, ...}, "mean": scores}.

    Each level is read with the imperfections the suite gives it, over those the checkpoint was trained
    with; `sensor_noise` replaces both for every level.
    """
    from softarm.learn.checkpoint import load_checkpoint  # torch loads here, not when softarm is imported

    suite = read_suite(folder)
    state = load_checkpoint(checkpoint)
    scorer = CaseScorer(state, Path(checkpoint))
    per_family: dict[str, dict[str, list[dict[str, np.ndarray]]]] = {f: {a: [] for a in ANSWERS} for f in suite.families}
    confidence, iou = [], []
    for done, case in enumerate(suite.cases, 1):
        scores, trust = scorer.score(case, sensor_noise)
        for answer, answer_scores in scores.items():
            per_family[case.family][answer].append(answer_scores)
        confidence.append(trust)
        iou.append(scores["model"]["iou"])
        if progress:
            progress(done, len(suite.cases))
    families = {name: family_scores(parts) for name, parts in per_family.items()}
    return {"suite": suite.version, "checkpoint": str(checkpoint), "families": families,
            "mean": mean_over_families(families), "confidence": confidence_scores(np.concatenate(confidence),
                                                                                   np.concatenate(iou)),
            "probes": suite.probes}


class CaseScorer:
    """Everything that is the same for every recording: networks, scalers, baselines, sensors."""

    def __init__(self, state: dict[str, Any], checkpoint: Path):
        from softarm.learn.imaginer import Imaginer
        from softarm.learn.baselines import Baselines
        self.state, self.checkpoint = state, checkpoint
        self.imaginer = Imaginer.from_checkpoint(state)
        self.baselines = Baselines.from_checkpoint(state)

    def score(self, case: SuiteCase, sensor_noise: Optional[dict[str, Any]]
              ) -> tuple[dict[str, dict[str, np.ndarray]], np.ndarray]:
        """Per-frame scores of every answer on one recording, and the model's confidence in each frame."""
        from softarm.imagine.replay import read_as_trained
        from softarm.learn.baselines import ridge_predict
        from softarm.learn.codes import encode_frames
        from softarm.learn.metrics import frame_scores

        noise = sensor_noise if sensor_noise is not None else case.sensing
        rec, stretch, _ = read_as_trained(self.state, self.checkpoint, case.path, noise)
        imaginer = self.imaginer
        windows, targets = imaginer.windows(stretch)
        truth = rec.frames[targets]
        ridge = ridge_predict(self.baselines.ridge, imaginer.stretch_scaler.forward(windows))
        ceiling = imaginer.latent_scaler.forward(encode_frames(imaginer.autoencoder, truth))
        ppm = rec.pixels_per_metre
        prediction = imaginer.predict(stretch)
        answers = {"model": imaginer.decode(prediction.latents), "ridge": imaginer.decode(ridge),
                   "ae_ceiling": imaginer.decode(ceiling),
                   "mean_frame": np.broadcast_to(self.baselines.mean_frame, truth.shape)}
        return {name: frame_scores(probs, truth, ppm) for name, probs in answers.items()}, prediction.confidence


def family_scores(parts: dict[str, list[dict[str, np.ndarray]]]) -> dict[str, Any]:
    """One family's row: the model's means and skill, the frame count, and every baseline's means."""
    from softarm.learn.metrics import summarise

    means = {answer: summarise({k: np.concatenate([p[k] for p in parts[answer]]) for k in parts[answer][0]})
             for answer in ANSWERS}
    row = {key: means["model"][key] for key in ("iou", "bce")}
    row["tip_error_mm"] = means["model"]["tip_mm"]
    row["tip_error_median_mm"] = float(np.nanmedian(np.concatenate([p["tip_mm"] for p in parts["model"]])))
    row["skill"] = skill(means["model"]["iou"], means["mean_frame"]["iou"], means["ae_ceiling"]["iou"])
    row["frames"] = int(sum(len(p["iou"]) for p in parts["model"]))
    row["baselines"] = {answer: {"iou": means[answer]["iou"], "bce": means[answer]["bce"],
                                 "tip_error_mm": means[answer]["tip_mm"]} for answer in ANSWERS[1:]}
    row["baselines"]["ridge"]["skill"] = skill(means["ridge"]["iou"], means["mean_frame"]["iou"],
                                               means["ae_ceiling"]["iou"])
    return row


def confidence_scores(confidence: np.ndarray, iou: np.ndarray) -> dict[str, float]:
    """How well the confidence ranks imagined frames by their true IoU, over every frame of the suite: the
    Spearman correlation, and the mean IoU of the least-trusted LEAST_TRUSTED of frames against the rest's."""
    from softarm.learn.metrics import spearman

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
