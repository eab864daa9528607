"""The confidence scores against brute-force definitions."""

import numpy as np
import pytest

from softarm.model.prediction import Prediction
from softarm.trust.confidence import ErrorHeadTrust
from softarm.trust.scoring import FRACTIONS, auroc, sparsification, trust_scores


def test_auroc_counts_the_pairs_a_positive_wins():
    rng = np.random.default_rng(0)
    score = rng.integers(0, 20, 300).astype(float)  # ties too
    positive = rng.random(300) < 0.3
    wins = [(1.0 if p > n else 0.5 if p == n else 0.0) for p in score[positive] for n in score[~positive]]
    assert auroc(score, positive) == np.mean(wins)
    assert np.isnan(auroc(score, np.zeros(300, bool)))


def test_sparsification_drops_the_lowest_scored_first():
    rng = np.random.default_rng(1)
    iou, score = rng.random(200), rng.random(200)
    curve = sparsification(score, iou)
    for fraction, value in zip(FRACTIONS, curve):
        dropped = int(round(fraction * 200))
        assert np.isclose(value, iou[np.argsort(score)][dropped:].mean())


def test_a_perfect_ranking_has_no_sparsification_error_and_a_random_one_does():
    rng = np.random.default_rng(2)
    iou = rng.random(1000)
    perfect = trust_scores(iou * 2, iou)
    assert perfect["ause"] == 0 and perfect["spearman"] == 1 and perfect["auroc"] == 1
    noisy = trust_scores(rng.random(1000), iou)
    assert noisy["ause"] > 0.1 and abs(noisy["spearman"]) < 0.1 and 0.4 < noisy["auroc"] < 0.6


def test_the_calibrated_reference_sees_what_its_spread_implies():
    decode = lambda z: np.repeat((np.arange(10) < z[:, :1] * 5 + 5)[:, None, :], 3, axis=1).astype(float)  # noqa: E731
    def reference(variance: float) -> np.ndarray:
        prediction = Prediction(np.arange(400), np.full((400, 2), 0.1), np.full((400, 2), np.log(variance)))
        return ErrorHeadTrust().reference_iou(prediction, decode(prediction.latents), decode, np.random.default_rng(0))

    assert (reference(1e-12) == 1).all()
    assert reference(1.0).mean() < reference(0.01).mean() < 1


def test_an_obstacle_is_labelled_by_the_frames_a_free_node_is_inside_it():
    """Two nodes, the first driven: the free one crosses a disc of radius 0.1 at the origin while |x| < 0.1; the
    recorded `touching` and, for an older recording, the positions give the same label, onsets and scores."""
    from softarm.trust.detection import case_surprise, surprise_report

    t = np.arange(100) * 0.01
    positions = np.zeros((100, 2, 2))
    positions[:, 1, 0] = np.linspace(-0.5, 0.5, 100)
    positions[:, 0] = 0.0  # the driven node sits inside the disc and must not count
    obstacle = {"kind": "obstacle", "start": 0.0, "end": None, "centre": [0.0, 0.0], "radius": 0.1}
    free = np.array([False, True])
    targets = np.arange(5, 100)
    inside = np.abs(positions[:, 1, 0]) < 0.1
    surprise = np.where(inside[targets], 5.0, 1.0)
    active = np.ones((100, 1), bool)
    recorded = case_surprise("contact", surprise, targets, t, active, [obstacle], touching=inside[:, None])
    older = case_surprise("contact", surprise, targets, t, active, [obstacle], positions=positions, free=free)
    calm = case_surprise("multisine_low", np.ones(95), targets, t, np.zeros((100, 0), bool), [])
    first = int(np.flatnonzero(inside[targets])[0])
    for case in (recorded, older):
        np.testing.assert_array_equal(case.active, inside[targets])
        assert case.present.all() and case.onsets == [(first, first + 20)] and case.first_touches == (first,)
        row = surprise_report([case, calm], 3.0, 0.01)["families"]["contact"]
        assert row["auroc"] == 1.0 and row["disturbances"] == 1 and row["latency_ms_suite"] == 0.0
        # the older view: the 20 touched frames outrank the 95 negatives, the other 75 tie with them
        assert row["auroc_present"] == (20 * 95 + 0.5 * 75 * 95) / (95 * 95) and row["touching_share"] == 20 / 95
        assert first > 0 and row["first_touch_ms"] == pytest.approx(first * 10.0)


def test_a_contact_recording_never_touched_is_disturbed_not_calm():
    from softarm.trust.detection import case_surprise

    t, targets = np.arange(50) * 0.01, np.arange(50)
    obstacle = {"kind": "obstacle", "start": 0.0, "end": None, "centre": [9.0, 9.0], "radius": 0.1}
    case = case_surprise("contact", np.ones(50), targets, t, np.ones((50, 1), bool), [obstacle],
                         touching=np.zeros((50, 1), bool))
    assert case.disturbed and not case.active.any() and case.onsets == [] and case.first_touches == ()


def test_false_alarms_are_counted_family_by_family_at_the_checkpoints_threshold():
    from softarm.trust.detection import case_surprise, surprise_report

    t, targets = np.arange(600) * 0.01, np.arange(600)
    jumpy = np.ones(600)
    jumpy[[100, 101, 300, 450]] = 5.0        # three alarms start above 3 (100-101 is one)
    cases = [case_surprise("sine_fast", jumpy, targets, t, np.zeros((600, 0), bool), []),
             case_surprise("multisine_low", np.ones(600), targets, t, np.zeros((600, 0), bool), []),
             case_surprise("multisine_low", np.where(np.arange(600) == 10, 4.0, 1.0), targets, t,
                           np.zeros((600, 0), bool), [])]
    report = surprise_report(cases, 3.0, 0.01)
    assert report["false_alarms_per_minute_by_family"] == {"sine_fast": 3 / 0.1, "multisine_low": 1 / 0.2}
    assert report["false_alarms_per_minute"]["own"] == pytest.approx(4 / 0.3)
