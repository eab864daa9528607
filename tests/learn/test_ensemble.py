"""An ensemble: its members train from their own seeds, its answer is their mean and its spread their variance
(checked against each member answering alone), a finished model grows members on --resume without training
again what it had, and a checkpoint's confidence can be the members' disagreement."""

import shutil

import numpy as np
import pytest
import torch

from softarm.config import load_config
from softarm.imagine.imaginer import Imaginer
from softarm.imagine.trained import TrainedModel
from softarm.learn.training import train
from softarm.model.checkpoint import load_checkpoint
from softarm.record.reader import read_recording
from tests.helpers.tiny import TINY

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def test_an_ensemble_answers_with_its_members_mean_and_variance(recordings, tmp_path):
    config = load_config(overrides={**TINY, "train.ensemble": 3, "train.confidence": "ensemble"})
    result = train([recordings / "s0.mcap"], config, tmp_path / "e.pt")
    assert result.complete and len(load_checkpoint(result.checkpoint)["members"]) == 2
    model = TrainedModel(result.checkpoint)
    imaginer = model.imaginer
    stretch = read_recording(recordings / "s1.mcap", nodes=False).stretch
    alone = [Imaginer(imaginer.autoencoder, m, imaginer.latent_scaler, imaginer.inputs).predict(stretch).latents
             for m in (imaginer.latent, *imaginer.members)]
    prediction = imaginer.predict(stretch)
    np.testing.assert_allclose(prediction.latents, np.mean(alone, axis=0), rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(prediction.spread, np.var(alone, axis=0), rtol=1e-4, atol=1e-8)
    assert np.abs(alone[1] - alone[0]).max() > 1e-3  # the members differ
    np.testing.assert_allclose(imaginer.confidence(prediction), 1 / (1 + prediction.spread.mean(axis=1)))
    assert len(load_checkpoint(result.checkpoint)["losses"]["members_val"]) == 2 * 12  # two members, 12 epochs each


def test_a_finished_model_grows_its_ensemble_on_resume(recordings, tiny_checkpoint, tmp_path):
    copy = tmp_path / "grown.pt"
    shutil.copy(tiny_checkpoint.checkpoint, copy)
    before = load_checkpoint(copy)
    result = train([recordings / "s0.mcap"], load_config(overrides={**TINY, "train.ensemble": 2}), copy, resume=True)
    after = load_checkpoint(copy)
    assert result.complete and len(after["members"]) == 1
    for key, weights in before["latent_model"].items():
        assert torch.equal(weights, after["latent_model"][key])  # the first model is not trained again
    assert after["config"]["train"]["ensemble"] == 2 and TrainedModel(copy).imaginer.members
