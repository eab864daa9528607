"""The calibrated confidence is a least-squares map fitted on the held-out frames: on those frames its predicted
log(1 - IoU + margin) has the mean of the true one (the property of a fit with a constant), computed here from a
replay of the training recording. Among its features, what the decoder draws: its doubt and the arm's area."""

import numpy as np
import pytest

from softarm.imagine.replay_data import compute_replay
from softarm.imagine.trained import TrainedModel
from softarm.model.baselines import ridge_predict
from softarm.model.prediction import picture_of
from softarm.trust.confidence import CalibratedTrust


def test_the_picture_is_the_decoders_doubt_and_the_arms_area():
    """Pixels the decoder is sure of carry no doubt and count whole; an undecided pixel carries ln 2 nats."""
    sure = np.zeros((1, 6, 4))
    sure[0, 2:5, 1:3] = 1.0
    undecided = np.full((1, 6, 4), 0.5)
    np.testing.assert_allclose(picture_of(np.concatenate([sure, undecided]).astype(np.float32)),
                               [[0.0, 6.0], [24 * np.log(2.0), 12.0]], atol=1e-9)
    frames = np.random.default_rng(0).uniform(size=(2500, 3, 5))  # more frames than one float64 batch
    p = frames.astype(np.float64)
    np.testing.assert_allclose(picture_of(frames)[:, 0], -(p * np.log(p) + (1 - p) * np.log(1 - p)).sum(axis=(1, 2)))


@pytest.mark.slow  # fits on a trained checkpoint: seconds
def test_the_calibrated_map_is_fitted_on_the_held_out_frames(recordings, tiny_checkpoint):
    model = TrainedModel(tiny_checkpoint.checkpoint)
    calibration = model.state["calibration"]
    assert calibration["frames"] == 40  # the 4 s recording's test segment: frames 340-379
    trust = CalibratedTrust.build(calibration)
    replay = compute_replay(tiny_checkpoint.checkpoint, recordings / "s0.mcap", nodes=False)
    prediction, _ = model.imaginer.imagine(model.read(recordings / "s0.mcap").inputs)
    np.testing.assert_allclose(prediction.picture, picture_of(replay.imagined[prediction.targets]), rtol=1e-6)
    held_out = (prediction.targets >= 340) & (prediction.targets < 380)
    truth = np.log(1 - replay.iou[prediction.targets[held_out]] + CalibratedTrust.MARGIN)
    predicted = trust.predicted(prediction.take(held_out))
    assert abs(predicted.mean() - truth.mean()) < 1e-4
    assert np.isclose(np.std(truth - predicted), calibration["spread"], rtol=1e-3)
    confidence = trust.confidence(prediction)
    assert ((confidence > 0) & (confidence <= 1)).all()


@pytest.mark.slow
def test_the_ridge_gap_is_the_distance_to_the_ridge_baseline_and_older_maps_still_read(recordings, tiny_checkpoint):
    """The gap is the one the suite's ridge baseline scores (the checkpoint's ridge on the same windows); maps
    fitted before the gap existed (three features and a constant) or before the picture (five) still give a
    confidence, the latter without drawing the frames."""
    model = TrainedModel(tiny_checkpoint.checkpoint)
    inputs = model.read(recordings / "s0.mcap").inputs
    prediction = model.imaginer.predict(inputs)
    windows, targets = model.imaginer.windows(inputs)
    ridge = ridge_predict(model.baselines.ridge, windows)[np.searchsorted(targets, prediction.targets)]
    np.testing.assert_allclose(prediction.ridge_gap, ((prediction.latents - ridge) ** 2).mean(axis=1), rtol=1e-9)
    calibration = model.state["calibration"]
    assert calibration["ridge_gap"] and calibration["picture"] and len(calibration["weights"]) == 7
    assert not CalibratedTrust.build(calibration).available(prediction)  # the frames are not drawn yet
    before_picture = CalibratedTrust.build({"weights": [0.5, 0.1, 0.2, 0.3, -2.0], "spread": 0.4, "ridge_gap": True})
    assert before_picture.available(prediction)
    np.testing.assert_allclose(before_picture.predicted(prediction) - 0.3 * np.log(prediction.ridge_gap + 1e-3),
                               CalibratedTrust.build({"weights": [0.5, 0.1, 0.2, -2.0], "spread": 0.4}
                                                     ).predicted(prediction))
    older = CalibratedTrust.build({"weights": [0.5, 0.1, 0.2, -2.0], "spread": 0.4})
    assert older.available(prediction)
    expected = 0.5 * np.log(np.exp(prediction.log_error).mean(axis=1)) - 2.0 + sum(
        w * np.log(np.nan_to_num(x, nan=1.0) + 0.1)
        for w, x in ((0.1, prediction.surprise), (0.2, prediction.residual)))
    np.testing.assert_allclose(older.predicted(prediction), expected)
