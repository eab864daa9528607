"""The calibrated confidence is a least-squares map fitted on the held-out frames: on those frames its predicted
log(1 - IoU + margin) has the mean of the true one (the property of a fit with a constant), computed here from a
replay of the training recording."""

import numpy as np

from softarm.imagine.replay import compute_replay
from softarm.model.trained import TrainedModel
from softarm.model.trust import CalibratedTrust


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
