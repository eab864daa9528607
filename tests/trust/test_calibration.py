"""The calibrated confidence is a least-squares map fitted on the held-out frames: on those frames its predicted
log(1 - IoU + margin) has the mean of the true one (the property of a fit with a constant), computed here from a
replay of the training recording."""

import numpy as np
import pytest

from softarm.imagine.replay_data import compute_replay
from softarm.imagine.trained import TrainedModel
from softarm.model.baselines import ridge_predict
from softarm.trust.confidence import CalibratedTrust

pytestmark = pytest.mark.slow  # each test fits on a trained checkpoint: seconds


def test_the_calibrated_map_is_fitted_on_the_held_out_frames(recordings, tiny_checkpoint):
    model = TrainedModel(tiny_checkpoint.checkpoint)
    calibration = model.state["calibration"]
    assert calibration["frames"] == 40  # the 4 s recording's test segment: frames 340-379
    trust = CalibratedTrust.build(calibration)
    replay = compute_replay(tiny_checkpoint.checkpoint, recordings / "s0.mcap", nodes=False)
    prediction = model.imaginer.predict(model.read(recordings / "s0.mcap").inputs)
    held_out = (prediction.targets >= 340) & (prediction.targets < 380)
    truth = np.log(1 - replay.iou[prediction.targets[held_out]] + CalibratedTrust.MARGIN)
    predicted = trust.predicted(prediction.take(held_out))
    assert abs(predicted.mean() - truth.mean()) < 1e-4
    assert np.isclose(np.std(truth - predicted), calibration["spread"], rtol=1e-3)
    confidence = trust.confidence(prediction)
    assert ((confidence > 0) & (confidence <= 1)).all()


def test_the_ridge_gap_is_the_distance_to_the_ridge_baseline_and_older_maps_still_read(recordings, tiny_checkpoint):
    """The gap is the one the suite's ridge baseline scores (the checkpoint's ridge on the same windows); a map
    fitted before the gap existed (three features and a constant) still gives a confidence."""
    model = TrainedModel(tiny_checkpoint.checkpoint)
    inputs = model.read(recordings / "s0.mcap").inputs
    prediction = model.imaginer.predict(inputs)
    windows, targets = model.imaginer.windows(inputs)
    ridge = ridge_predict(model.baselines.ridge, windows)[np.searchsorted(targets, prediction.targets)]
    np.testing.assert_allclose(prediction.ridge_gap, ((prediction.latents - ridge) ** 2).mean(axis=1), rtol=1e-9)
    assert model.state["calibration"]["ridge_gap"] and len(model.state["calibration"]["weights"]) == 5
    older = CalibratedTrust.build({"weights": [0.5, 0.1, 0.2, -2.0], "spread": 0.4})
    assert older.available(prediction)
    expected = 0.5 * np.log(np.exp(prediction.log_error).mean(axis=1)) - 2.0 + sum(
        w * np.log(np.nan_to_num(x, nan=1.0) + 0.1)
        for w, x in ((0.1, prediction.surprise), (0.2, prediction.residual)))
    np.testing.assert_allclose(older.predicted(prediction), expected)
