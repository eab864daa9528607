"""How well the surprise notices the world acting on the arm, family by family of the suite.

Per disturbance family: the per-frame AUROC of the surprise against the recording's own label of a
disturbance acting (`/arm/disturbance`), the family's undisturbed frames and every frame of the motion families
as the negatives; and the latency from each disturbance's onset to the first alarm before it ends (a miss when
none comes), at two thresholds: the checkpoint's own (set on its training motion), and the lowest that starts at
most `PER_MINUTE` false alarms a minute over the suite's undisturbed families, `sensor_noise` among them (its
sensors are noisier than the model's, and the surprise expects the noise it is told of:
`SurpriseModel.heard_through`). An obstacle is labelled by the frames the arm touches it in (the recording's
`touching`), the label of contact; where one stands, the AUROC against its whole interval stays as a second,
named view (`presence_scores`).
"""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from softarm.trust.alarm import alarm_onsets, alarm_threshold, runs
from softarm.trust.scoring import auroc

PER_MINUTE = 1.0


@dataclass(frozen=True)
class CaseSurprise:
    """One recording's surprise at its imagined frames, the frames the world acts on the body in, and the onsets
    to answer. A push, a payload or damage acts through its interval; an obstacle acts only while the arm touches
    it (the recording's `touching`, docs/recording.md), so its frames are the touches and each touch is an onset.
    Where an obstacle stands, `present` keeps the older view, every frame from the obstacle's start, and
    `first_touches` how long each obstacle stood before the arm first touched it."""
    family: str
    surprise: np.ndarray             # (M,)
    active: np.ndarray               # (M,) bool: the label
    onsets: list[tuple[int, int]]    # [start, end) positions into the M frames
    disturbed: bool = False          # the recording lists any disturbance (an obstacle never touched counts)
    present: Optional[np.ndarray] = None  # (M,) bool, where an obstacle stands: any disturbance present
    first_touches: tuple[int, ...] = ()   # frames from each touched obstacle's onset to its first touch


def case_surprise(family: str, surprise: np.ndarray, targets: np.ndarray, times: np.ndarray, active: np.ndarray,
                  disturbances: list[dict[str, Any]], touching: Optional[np.ndarray] = None,
                  positions: Optional[np.ndarray] = None, free: Optional[np.ndarray] = None) -> CaseSurprise:
    """`active` and `touching` (T, D) as the recording gives them, `targets` (M,) the imagined frames. A recording
    written before `touching` was defined gives `positions` (T, N, 2) and `free` (N,) bool instead: the touches
    are then the frames in which a free node is inside an active obstacle, as the recorder marks them."""
    intervals = []
    for d in disturbances:
        start = int(np.searchsorted(times[targets], float(d["start"]) - 1e-9))
        end = len(targets) if d.get("end") is None else int(np.searchsorted(times[targets], float(d["end"]) - 1e-9))
        intervals.append((start, end))
    present = active[targets].any(axis=1) if active.size else np.zeros(len(targets), bool)
    obstacle = np.array([d["kind"] == "obstacle" for d in disturbances], bool)
    touches = touching[targets] if touching is not None else _touches(targets, active, disturbances, positions, free)
    if not obstacle.any() or touches is None:
        return CaseSurprise(family, surprise, present, [(s, e) for s, e in intervals if e > s], bool(disturbances))
    label = active[targets][:, ~obstacle].any(axis=1) | touches[:, obstacle].any(axis=1)
    onsets = [(s, e) for (s, e), o in zip(intervals, obstacle) if e > s and not o]
    onsets += [run for d in np.flatnonzero(obstacle) for run in runs(touches[:, d])]
    first = [np.flatnonzero(touches[s:e, d]) for d, (s, e) in enumerate(intervals) if obstacle[d]]
    return CaseSurprise(family, surprise, label, onsets, True, present, tuple(int(f[0]) for f in first if len(f)))


def _touches(targets: np.ndarray, active: np.ndarray, disturbances: list[dict[str, Any]],
             positions: Optional[np.ndarray], free: Optional[np.ndarray]) -> Optional[np.ndarray]:
    """(M, D) bool: a free node inside an active obstacle at each imagined frame; None without positions."""
    if positions is None:
        return None
    out = np.zeros((len(targets), len(disturbances)), bool)
    for n, d in enumerate(disturbances):
        if d["kind"] == "obstacle":
            gap = np.linalg.norm(positions[targets][:, free] - np.asarray(d["centre"]), axis=2)
            out[:, n] = active[targets, n] & (gap < float(d["radius"])).any(axis=1)
    return out


def surprise_report(cases: list[CaseSurprise], own_threshold: float, frame_dt: float) -> Optional[dict[str, Any]]:
    """{"families": {name: {auroc, latency_ms...}}, thresholds, false alarms}; None without a surprise."""
    if not cases or not any(np.isfinite(c.surprise).any() for c in cases):
        return None
    calm = [c for c in cases if not c.disturbed]
    negatives = np.concatenate([c.surprise for c in calm])
    suite_threshold = alarm_threshold([(c.surprise, np.ones(len(c.surprise), bool)) for c in calm], frame_dt,
                                      PER_MINUTE)
    families = {}
    for family in dict.fromkeys(c.family for c in cases if c.disturbed):
        mine = [c for c in cases if c.family == family]
        score = np.concatenate([*(c.surprise for c in mine), negatives])
        label = np.concatenate([*(c.active for c in mine), np.zeros(len(negatives), bool)])
        finite = np.isfinite(score)
        families[family] = {"auroc": auroc(score[finite], label[finite]),
                            "disturbances": sum(len(c.onsets) for c in mine),
                            **latencies(mine, suite_threshold, frame_dt, "suite"),
                            **latencies(mine, own_threshold, frame_dt, "own"), **presence_scores(mine, score, frame_dt)}
    return {"families": families, "thresholds": {"suite": suite_threshold, "own": own_threshold},
            "false_alarms_per_minute": {"suite": alarm_rate(calm, suite_threshold, frame_dt),
                                        "own": alarm_rate(calm, own_threshold, frame_dt)},
            "false_alarms_per_minute_by_family": {  # at the checkpoint's own threshold: what replay and the streamer do
                family: alarm_rate([c for c in calm if c.family == family], own_threshold, frame_dt)
                for family in dict.fromkeys(c.family for c in calm)},
            "per_minute_goal": PER_MINUTE}


def presence_scores(cases: list[CaseSurprise], score: np.ndarray, frame_dt: float) -> dict[str, float]:
    """Where obstacles stand, the older view beside the touches: the AUROC against every frame an obstacle stands
    in (the rest of the family's frames and the undisturbed families' as negatives), the share of those frames
    the arm touches it in, and the median time from an obstacle's onset to the arm's first touch, before which
    nothing acts on the body to be felt. `score` is the family's AUROC input: its cases' frames, then the
    negatives."""
    if not cases or any(c.present is None for c in cases):
        return {}
    present = np.concatenate([c.present for c in cases])
    touched = np.concatenate([c.active & c.present for c in cases])
    label = np.zeros(len(score), bool)
    label[:len(present)] = present
    finite = np.isfinite(score)
    reached = [f * frame_dt * 1e3 for c in cases for f in c.first_touches]
    return {"auroc_present": auroc(score[finite], label[finite]),
            "touching_share": float(touched.sum() / max(present.sum(), 1)),
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
