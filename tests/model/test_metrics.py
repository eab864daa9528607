"""Image scores against hand-computed values and a plain per-pixel loop."""

import math

import numpy as np
import pytest

from softarm.model.baselines import ridge_fit, ridge_predict
from softarm.model.metrics import frame_scores, image_scores, summarise, tip_pixels


def test_scores_of_a_hand_made_pair():
    truth = np.zeros((1, 6, 4), np.uint8)
    truth[0, 1:5, 1:3] = 1                       # 8 pixels, lowest row 4, columns 1-2
    prob = np.zeros((1, 6, 4), np.float32)
    prob[0, 2:6, 1:3] = 0.9                      # 8 pixels, 6 shared; lowest row 5
    s = image_scores(prob, truth, pixels_per_metre=1000.0)
    assert math.isclose(s["iou"], 6 / 10) and math.isclose(s["dice"], 12 / 16)
    assert math.isclose(s["tip_mm"], 1.0)        # one pixel down at 1000 px/m
    expected = -(6 * math.log(0.9) + 2 * math.log(1e-7) + 2 * math.log(0.1) + 14 * math.log(1 - 1e-7)) / 24
    assert math.isclose(s["bce"], expected, rel_tol=1e-5)


def test_frame_scores_match_a_pixel_loop_and_subsets_summarise():
    rng = np.random.default_rng(3)
    truth = (rng.random((7, 9, 5)) > 0.6).astype(np.uint8)
    prob = rng.random((7, 9, 5)).astype(np.float32)
    per_frame = frame_scores(prob, truth, 100.0, chunk=3)
    for n in range(7):
        p, t = prob[n] >= 0.5, truth[n] > 0
        assert math.isclose(per_frame["iou"][n], (p & t).sum() / (p | t).sum())
    mask = np.array([1, 0, 1, 1, 0, 0, 1], bool)
    assert summarise(per_frame, mask) == image_scores(prob[mask], truth[mask], 100.0)


def test_tip_is_the_centroid_of_the_lowest_arm_row_and_nan_for_empty_frames():
    frames = np.zeros((2, 10, 8))
    frames[0, 3:7, 2:6] = 1
    frames[0, 7, 4:7] = 1
    np.testing.assert_allclose(tip_pixels(frames)[0], [5.5, 7.5])
    assert np.isnan(tip_pixels(frames)[1]).all()


def test_ridge_recovers_a_linear_map():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(400, 3, 2))
    w = rng.normal(size=(6, 4))
    y = x.reshape(400, -1) @ w + 0.5
    model = ridge_fit(x, y, alpha=1e-8)
    np.testing.assert_allclose(ridge_predict(model, x), y, atol=1e-5)


def test_spearman_matches_the_pearson_correlation_of_ranks_and_shares_tied_ranks():
    from softarm.model.metrics import average_ranks, spearman

    rng = np.random.default_rng(3)
    a, b = rng.normal(size=200), rng.normal(size=200)
    ranks = lambda x: np.argsort(np.argsort(x)).astype(float)  # noqa: E731 (no ties: plain ranks)
    assert spearman(a, b) == pytest.approx(np.corrcoef(ranks(a), ranks(b))[0, 1])
    assert spearman(a, np.exp(a)) == pytest.approx(1.0) and spearman(a, -a) == pytest.approx(-1.0)
    assert average_ranks(np.array([5.0, 1.0, 5.0, 3.0])).tolist() == [2.5, 0.0, 2.5, 1.0]
