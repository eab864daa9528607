"""`softarm adapt`: the surprise's ridge toward the trained weights against a least-squares reference, what
fine-tuning differentiates equals each model's own answers, the adapted checkpoint fits the camera's frames
better than before, and what cannot be done is refused in one line."""

import numpy as np
import pytest
import torch

from softarm.config import load_config
from softarm.imagine.trained import TrainedModel
from softarm.learn.finetune import ridge_toward
from softarm.model.autoencoder import encode_frames
from tests.helpers.cli import assert_one_line_error, softarm


def test_the_ridge_toward_the_old_head_is_least_squares_with_a_prior():
    rng = np.random.default_rng(0)
    x, y = rng.standard_normal((50, 4)), rng.standard_normal((50, 3))
    w0, b0 = rng.standard_normal((4, 3)), rng.standard_normal(3)
    shrink = 0.2
    weights, bias = ridge_toward(x, y, w0, b0, shrink)
    xa = np.column_stack([x, np.ones(50)])
    root = np.sqrt(shrink * np.mean(xa ** 2) * 50)
    stacked = np.concatenate([xa, root * np.eye(5)])
    targets = np.concatenate([y, root * np.concatenate([w0, b0[None]])])
    expected = np.linalg.lstsq(stacked, targets, rcond=None)[0]
    np.testing.assert_allclose(np.concatenate([weights, bias[None]]), expected, atol=1e-10)


@pytest.fixture(scope="module")
def loaded(tmp_path_factory):
    """6 s with 10 g on each tip node from 2 s on."""
    from softarm.sim.simulate import simulate

    path = tmp_path_factory.mktemp("adapt") / "loaded.mcap"
    simulate(load_config(overrides={"run.duration": 6.0, "run.seed": 3, "disturbances": [
        {"kind": "payload", "start": 2.0, "mass": 0.01, "nodes": [54, 55, 56]}]}), path)
    return path


def latent_error(checkpoint, recording, frames):
    model = TrainedModel(checkpoint)
    reading = model.read(recording)
    prediction = model.imaginer.predict(reading.inputs)
    chosen = np.isin(prediction.targets, frames)
    truth = model.imaginer.latent_scaler.forward(encode_frames(model.imaginer.autoencoder,
                                                               reading.recording.frames[frames]))
    return float(np.mean((prediction.latents[chosen] - truth) ** 2))


@pytest.mark.slow
@pytest.mark.parametrize("fixture", ["tiny_window_checkpoint", "tiny_checkpoint"])
def test_the_latents_fine_tuning_differentiates_are_the_models_answers(loaded, fixture, request):
    model = TrainedModel(request.getfixturevalue(fixture).checkpoint)
    latent = model.imaginer.latent
    series = model.imaginer.normalised(model.read(loaded).inputs)
    prediction = latent.answer([series])[0]
    with torch.no_grad():
        at = latent.latents_at(torch.from_numpy(series), torch.from_numpy(prediction.targets[::37] - latent.lead))
    np.testing.assert_allclose(at.numpy(), prediction.latents[::37], atol=1e-5)


@pytest.mark.slow
def test_adapt_fits_the_seconds_of_camera_and_reports_the_rest(loaded, tiny_checkpoint, tmp_path):
    result = softarm("adapt", str(tiny_checkpoint.checkpoint), str(loaded), "--seconds", "2", "--out", "a.pt",
                     cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "from 2.00 s" in result.stdout and "IoU" in result.stdout
    window = np.arange(200, 400)  # the lasting disturbance's start, 2 s of camera
    assert latent_error(tmp_path / "a.pt", loaded, window) < latent_error(tiny_checkpoint.checkpoint, loaded, window)
    adaptation = TrainedModel(tmp_path / "a.pt").state["adaptation"]
    assert adaptation["camera_frames"] == 200 and adaptation["rest_frames"] == 200


@pytest.mark.slow
def test_adapt_refuses_what_it_cannot_do(loaded, tiny_checkpoint, tmp_path):
    too_long = softarm("adapt", str(tiny_checkpoint.checkpoint), str(loaded), "--seconds", "9", "--out", "a.pt",
                       cwd=tmp_path)
    assert_one_line_error(too_long, "past its end")
    over_input = softarm("adapt", str(tiny_checkpoint.checkpoint), str(loaded), "--seconds", "1", "--out",
                         str(tiny_checkpoint.checkpoint), "--force", cwd=tmp_path)
    assert_one_line_error(over_input, "input")
    assert not (tmp_path / "a.pt").exists()
