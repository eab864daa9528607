"""The auxiliary node target (`train.node_target`): a head that learns the node positions beside the latent,
for training only, and bf16 training's precision setting."""

import numpy as np
import pytest
import torch

from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.imagine.imaginer import Imaginer
from softarm.learn.dataset import load_dataset
from softarm.learn.node_targets import node_targets
from softarm.learn.training import train
from softarm.model.checkpoint import load_checkpoint
from softarm.model.inputs import channels
from softarm.record.reader import read_recording
from tests.helpers.tiny import TINY


def test_node_targets_are_the_positions_less_their_training_mean_over_one_spread(recordings):
    config = load_config(overrides={"run.duration": 4.0})
    data = load_dataset([recordings / "s0.mcap"], config, channels(["stretch"]))
    (targets,) = node_targets(data)
    positions = read_recording(recordings / "s0.mcap", nodes=True).positions.reshape(len(targets), -1)
    train_end = data.sequences[0].segment("train")[1]
    centred = positions - positions[:train_end].mean(axis=0)
    spread = centred[:train_end].std()
    np.testing.assert_allclose(targets, centred / spread, atol=1e-4)  # float32 positions and targets


@pytest.mark.slow
def test_a_model_trained_with_the_node_target_learns_the_nodes_and_answers_as_any_other(recordings, tmp_path):
    config = load_config(overrides={**TINY, "train.node_target": 1.0, "train.epochs_lstm": 40})
    result = train([recordings / "s0.mcap"], config, tmp_path / "nodes.pt")
    state = load_checkpoint(result.checkpoint)
    head = state["latent_model"]["nodes.weight"]
    assert head.shape == (2 * 57, config.train.lstm_hidden)
    imaginer = Imaginer.from_checkpoint(state)
    prediction, probs = imaginer.imagine(np.random.default_rng(0).normal(0, 1e-3, (20, 4)))
    assert probs.shape == (14, 84, 52) and prediction.latents.shape[1] == imaginer.latent_scaler.kept
    # the head's own answer on the training frames beats the mean position: it learned the body's shape
    data = load_dataset([recordings / "s0.mcap"], config, channels(["stretch"]))
    (targets,) = node_targets(data)
    latent = imaginer.latent
    with torch.no_grad():
        states, _ = latent.rnn(torch.from_numpy(imaginer.normalised(data.sequences[0].inputs))[None])
        guess = latent.nodes(states[0]).numpy()
    lead = config.train.lead
    error = np.mean((guess[:-lead] - targets[lead:]) ** 2)
    assert error < 0.5 * np.mean(targets[lead:] ** 2)


@pytest.mark.parametrize("key, value, words", [("train.node_target", -1.0, "train.node_target"),
                                               ("train.precision", "fp16", "train.precision")])
def test_bad_training_settings_are_refused_naming_the_key(key, value, words):
    with pytest.raises(ConfigError, match=words):
        load_config(overrides={key: value})
