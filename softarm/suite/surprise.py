"""How well the surprise notices the world acting on the arm, family by family of the suite.

Per disturbance family: the per-frame AUROC of the surprise against the recording's own label of a
disturbance acting (`/arm/disturbance`), the family's undisturbed frames and every frame of the motion families
as the negatives; and the latency from each disturbance's onset to the first alarm before it ends (a miss when
none comes), at two thresholds: the checkpoint's own (set on its training motion), and the lowest that starts at
most `PER_MINUTE` false alarms a minute over the suite's undisturbed families, `sensor_noise` among them (its
sensors are noisier than the model's, and the surprise expects the noise it is told of:
`SurpriseModel.heard_through`). Where an obstacle stands, also the AUROC against the frames the arm touches it in
and the bounds its label sets (`touch_scores`).
"""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from softarm.model.alarm import alarm_onsets, alarm_threshold
from softarm.suite.trust import auroc

PER_MINUTE = 1.0


@dataclass(frozen=True)
class CaseSurprise:
    """One recording's surprise at its imagined frames, which of them a disturbance acts on, and the
    disturbances' first and past-the-last imagined frame indices; where an obstacle stands, which frames the arm
    touches it in (the recording's label says the obstacle is there, not that the arm feels it)."""
    family: str
    surprise: np.ndarray             # (M,)
    active: np.ndarray               # (M,) bool
    onsets: list[tuple[int, int]]    # [start, end) positions into the M frames, one per disturbance
    touching: Optional[np.ndarray] = None  # (M,) bool, for a recording with an obstacle and its nodes


def case_surprise(family: str, surprise: np.ndarray, targets: np.ndarray, times: np.ndarray, active: np.ndarray,
                  disturbances: list[dict[str, Any]], positions: Optional[np.ndarray] = None,
                  free: Optional[np.ndarray] = None) -> CaseSurprise:
    """`active` (T, D) as the recording gives it; `targets` (M,) the imagined frames; `positions` (T, N, 2) and
    `free` (N,) bool, where given, mark the frames in which a free node is inside an active obstacle."""
    onsets = []
    for d in disturbances:
        start = int(np.searchsorted(times[targets], float(d["start"]) - 1e-9))
        end = len(targets) if d.get("end") is None else int(np.searchsorted(times[targets], float(d["end"]) - 1e-9))
        if end > start:
            onsets.append((start, end))
    label = active[targets].any(axis=1) if active.size else np.zeros(len(targets), bool)
    obstacles = [(n, d) for n, d in enumerate(disturbances) if d["kind"] == "obstacle"]
    touching = None
    if obstacles and positions is not None:
        touching = np.zeros(len(targets), bool)
        for n, d in obstacles:
            gap = np.linalg.norm(positions[targets][:, free] - np.asarray(d["centre"]), axis=2)
            touching |= active[targets, n] & (gap < float(d["radius"])).any(axis=1)
    return CaseSurprise(family, surprise, label, onsets, touching)


def surprise_report(cases: list[CaseSurprise], own_threshold: float, frame_dt: float) -> Optional[dict[str, Any]]:
    """{"families": {name: {auroc, latency_ms...}}, thresholds, false alarms}; None without a surprise."""
    if not cases or not any(np.isfinite(c.surprise).any() for c in cases):
        return None
    calm = [c for c in cases if not c.onsets]
    negatives = np.concatenate([c.surprise for c in calm])
    suite_threshold = alarm_threshold([(c.surprise, np.ones(len(c.surprise), bool)) for c in calm], frame_dt, PER_MINUTE)
    families = {}
    for family in dict.fromkeys(c.family for c in cases if c.onsets):
        mine = [c for c in cases if c.family == family]
        score = np.concatenate([*(c.surprise for c in mine), negatives])
        label = np.concatenate([*(c.active for c in mine), np.zeros(len(negatives), bool)])
        finite = np.isfinite(score)
        families[family] = {"auroc": auroc(score[finite], label[finite]), "disturbances": sum(len(c.onsets) for c in mine),
                            **latencies(mine, suite_threshold, frame_dt, "suite"),
                            **latencies(mine, own_threshold, frame_dt, "own"), **touch_scores(mine, score, label, frame_dt)}
    return {"families": families, "thresholds": {"suite": suite_threshold, "own": own_threshold},
            "false_alarms_per_minute": {"suite": alarm_rate(calm, suite_threshold, frame_dt),
                                        "own": alarm_rate(calm, own_threshold, frame_dt)},
            "per_minute_goal": PER_MINUTE}


def touch_scores(cases: list[CaseSurprise], score: np.ndarray, label: np.ndarray, frame_dt: float) -> dict[str, float]:
    """Where the family's recordings mark touches: the AUROC against the frames the arm touches (the rest of the
    family's frames and the undisturbed families' as negatives), the share of frames touching, and two bounds the
    label sets: the AUROC of a surprise that felt exactly the touches (a one-step forward model that knew the body
    whole: the obstacle pushes only while touched, and standing untouched it is felt by nothing), and the median
    time from an obstacle's onset to the arm's first touch, before which no alarm can answer it. `score` and
    `label` are the family's AUROC inputs: its cases' frames, then the negatives."""
    if not cases or any(c.touching is None for c in cases):
        return {}
    family = np.concatenate([c.touching for c in cases])
    touching = np.zeros(len(score), bool)
    touching[:len(family)] = family
    finite = np.isfinite(score)
    first = [np.flatnonzero(c.touching[start:end]) for c in cases for start, end in c.onsets]
    reached = [f[0] * frame_dt * 1e3 for f in first if len(f)]
    return {"auroc_touching": auroc(score[finite], touching[finite]), "touching_share": float(family.mean()),
            "auroc_touch_only": auroc(touching[finite].astype(float), label[finite]),
            "first_touch_ms": float(np.median(reached)) if reached else float("nan")}


def latencies(cases: list[CaseSurprise], threshold: float, frame_dt: float, name: str) -> dict[str, float]:
    """Median latency (ms) from onset to the first alarm frame before the disturbance ends, over the detected
    ones, and the share detected."""
    found = []
    for c in cases:
        for start, end in c.onsets:
            above = np.flatnonzero(np.nan_to_num(c.surprise[start:end]) > threshold)
            found.append(above[0] * frame_dt * 1e3 if len(above) else np.inf)
    detected = np.isfinite(found)
    return {f"latency_ms_{name}": float(np.median(np.asarray(found)[detected])) if detected.any() else float("nan"),
            f"detected_{name}": float(detected.mean()) if found else float("nan")}


def alarm_rate(cases: list[CaseSurprise], threshold: float, frame_dt: float) -> float:
    """Alarms started a minute over the cases' frames."""
    minutes = sum(len(c.surprise) for c in cases) * frame_dt / 60.0
    return sum(len(alarm_onsets(c.surprise, threshold)) for c in cases) / minutes if minutes else float("nan")
