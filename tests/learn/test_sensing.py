"""Training and replay read the sensors as [sensing] says: other node pairs, imperfections, the same
realisation for the same seed, and a checkpoint that replays with the sensors it was trained on."""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.imagine.replay_data import compute_replay
from softarm.learn.dataset import load_dataset
from softarm.learn.training import train
from softarm.model.inputs import channels
from tests.helpers.tiny import TINY


def test_the_dataset_reads_the_configured_imperfections_reproducibly(recordings):
    config = load_config(overrides={"sensing.noise": 1e-4, "sensing.seed": 3})
    ideal = load_dataset([recordings / "s0.mcap"], load_config(), channels()).sequences[0].inputs
    noisy = load_dataset([recordings / "s0.mcap"], config, channels()).sequences[0].inputs
    again = load_dataset([recordings / "s0.mcap"], config, channels()).sequences[0].inputs
    assert abs(np.std(noisy - ideal) - 1e-4) < 5e-6
    np.testing.assert_array_equal(noisy, again)


@pytest.mark.slow
def test_a_checkpoint_of_other_pairs_replays_any_recording_with_its_own_pairs(recordings, tmp_path):
    pairs = [[3, 54], [5, 56]]  # two long sensors, neither of them recorded
    config = load_config(overrides={**TINY, "train.epochs_ae": 2, "train.epochs_lstm": 2, "sensing.pairs": pairs})
    trained = train([recordings / "s0.mcap"], config, tmp_path / "pairs.pt")
    assert trained.complete
    result = compute_replay(trained.checkpoint, recordings / "s1.mcap", nodes=False)
    assert result.inputs.shape == (len(result.times), 2)
    assert result.metrics["sensing"]["pairs"] == pairs
    recorded = result.recording.stretch
    assert not np.allclose(result.inputs[:, 0], recorded[:, 0])  # recomputed, not the recorded sensor 0
