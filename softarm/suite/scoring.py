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

from softarm.registry import trust_classes
from softarm.suite.manifest import SuiteCase, read_suite
from softarm.trust.detection import CaseSurprise, case_surprise, surprise_report
from softarm.trust.scoring import FLAGGED, LEAST_TRUSTED, trust_scores, with_reference

if TYPE_CHECKING:
    from softarm.imagine.trained import TrainedModel

Progress = Callable[[int, int], None]


def evaluate_suite(checkpoint: Union[str, Path], folder: Union[str, Path],
                   sensor_noise: Optional[dict[str, Any]] = None, progress: Optional[Progress] = None,
                   device: str = "auto") -> dict[str, Any]:
    """The evaluation document: {"suite", "checkpoint", "families": {name: scores, ...}, "mean": scores}.

    Each level is read with the imperfections the suite gives it, over those the checkpoint was trained
    with; `sensor_noise` replaces both for every level.
    """
    from softarm.imagine.trained import TrainedModel  # torch loads here, not when softarm is imported

    suite = read_suite(folder)
    model = TrainedModel(checkpoint, device)
    scorer = CaseScorer(model)
    per_family: dict[str, dict[str, list[dict[str, np.ndarray]]]] = {f: {} for f in suite.families}
    trust: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    iou, felt = [], []
    for done, case in enumerate(suite.cases, 1):
        scores, methods, surprise = scorer.score(case, sensor_noise)
        for answer, answer_scores in scores.items():
            per_family[case.family].setdefault(answer, []).append(answer_scores)
        for name, parts in methods.items():
            trust.setdefault(name, []).append(parts)
        iou.append(scores["model"]["iou"])
        felt.append(surprise)
        if progress:
            progress(done, len(suite.cases))
    families = {name: family_scores(parts) for name, parts in per_family.items()}
    groups = {group: {f: families[f] for f in families if suite.groups[f] == group}
              for group in dict.fromkeys(suite.groups.values())}
    return {"suite": suite.version, "checkpoint": str(checkpoint), "families": families,
            "mean": mean_over_families(families),
            "group_means": {group: mean_over_families(rows) for group, rows in groups.items()},
            "confidence": confidence_report(trust, np.concatenate(iou), model.config.train.confidence),
            "surprise": surprise_report(felt, model.imaginer.surprise.threshold if model.imaginer.surprise else np.nan,
                                        model.config.integration.frame_dt),
            "probes": suite.probes, "groups": suite.groups}


class CaseScorer:
    """One trained model scoring recording after recording."""

    def __init__(self, model: "TrainedModel"):
        self.model = model
        self.ways = [way for way in (cls.build(model.state.get("calibration")) for cls in trust_classes()) if way]

    def score(self, case: SuiteCase, sensor_noise: Optional[dict[str, Any]]
              ) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, tuple[np.ndarray, np.ndarray]], CaseSurprise]:
        """Per-frame scores of every answer on one recording; every confidence the checkpoint can give of each
        frame with the IoU a calibrated predictor of its spread would see there; the frames' surprise."""
        from softarm.imagine.answers import PRIVILEGED, score_answers, score_node_ridge
        from softarm.model.autoencoder import encode_frames
        from softarm.record.reader import read_model

        obstacles = any(d.get("kind") == "obstacle" for d in read_model(case.path).get("disturbances", []))
        reading = self.model.read(case.path, sensor_noise if sensor_noise is not None else case.sensing,
                                  nodes=obstacles)
        imaginer = self.model.imaginer_for(reading.config)
        windows, targets = imaginer.windows(reading.inputs)
        truth = reading.recording.frames[targets]
        ceiling = imaginer.latent_scaler.forward(encode_frames(imaginer.autoencoder, truth))
        prediction = imaginer.predict(reading.inputs)
        rec, baselines = reading.recording, self.model.baselines
        answer = imaginer.decode(prediction.latents)
        prediction = prediction.with_picture(answer)
        scores = score_answers(imaginer, baselines, truth, answer, windows, ceiling, rec.pixels_per_metre)
        if baselines.nodes is not None:
            scores[PRIVILEGED] = score_node_ridge(imaginer, baselines, reading.inputs, targets, truth, rec.model,
                                                  rec.pixels_per_metre)
        rng = np.random.default_rng(0)
        methods = {trust.name: (trust.confidence(prediction),
                                trust.reference_iou(prediction, answer, imaginer.decode, rng))
                   for trust in self.ways if trust.available(prediction)}
        surprise = prediction.surprise if prediction.surprise is not None else np.full(len(targets), np.nan)
        free = np.ones(len(rec.model["masses"]), bool)
        free[rec.model["driven"]] = False
        return scores, methods, case_surprise(case.family, surprise, targets, rec.times, rec.active,
                                              rec.model.get("disturbances", []), rec.touching, rec.positions, free)


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


def confidence_report(trust: dict[str, list[tuple[np.ndarray, np.ndarray]]], iou: np.ndarray,
                      chosen: str) -> dict[str, Any]:
    """Every confidence's scores over every frame of the suite, each with its reference values."""
    methods = {}
    for name, parts in trust.items():
        confidence, reference = (np.concatenate(a) for a in zip(*parts))
        methods[name] = with_reference(trust_scores(confidence, iou), trust_scores(confidence, reference))
    return {"default": chosen, "methods": methods, "least_trusted_share": LEAST_TRUSTED, "flagged_below": FLAGGED}


def skill(iou: float, floor: float, ceiling: float) -> float:
    """Share of the gain from the mean frame to the AE ceiling that an answer reaches (1: all of it)."""
    return (iou - floor) / (ceiling - floor) if ceiling > floor else float("nan")


def mean_over_families(families: dict[str, dict[str, Any]]) -> dict[str, float]:
    """Every family weighs the same, whatever its frame count."""
    keys = ("iou", "bce", "tip_error_mm", "tip_error_median_mm", "skill")
    return {key: float(np.nanmean([row[key] for row in families.values()])) for key in keys}
