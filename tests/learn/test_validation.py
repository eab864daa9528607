"""A corpus keeps whole recordings out of training, and its metrics score them apart."""

import pytest

from softarm.config import load_config
from softarm.learn.dataset import load_dataset, validation_indices
from softarm.model.inputs import channels
from tests.helpers.tiny import TINY


def test_validation_recordings_are_spread_over_a_corpus_and_none_of_a_few():
    assert validation_indices(4, 0.1) == set() and validation_indices(64, 0.0) == set()
    assert validation_indices(5, 0.1) == {2}
    kept = sorted(validation_indices(64, 0.1))
    assert len(kept) == 6 and kept[0] < 11 and kept[-1] > 53


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    from softarm.sim.simulate import simulate

    folder = tmp_path_factory.mktemp("corpus")
    simulate(load_config(overrides={"run.duration": 2.0, "run.arms": 5}), folder / "c.mcap")
    return sorted(folder.glob("*.mcap"))


@pytest.mark.slow
def test_a_held_out_recording_trains_nothing_and_is_validated_whole(corpus):
    config = load_config()
    data = load_dataset(corpus, config, channels())
    assert [s.held_out for s in data.sequences] == [False, False, True, False, False]
    held = data.sequences[2]
    assert held.segment("train") == (0, 0) and held.segment("test") == (0, 190)
    assert data.count("train") == 4 * 170


@pytest.mark.slow
def test_training_on_a_corpus_reports_the_held_out_recordings(corpus, tmp_path):
    from softarm.learn.training import train

    result = train(corpus, load_config(overrides={**TINY, "train.model": "stream", "train.epochs_lstm": 3}),
                   tmp_path / "c.pt")
    validation = result.metrics["validation"]
    assert validation["recordings"] == [corpus[2].name]
    assert set(validation) >= {"model", "ridge", "mean_frame", "ae_ceiling"}
    assert 0 <= validation["model"]["iou"] <= 1


@pytest.mark.slow
def test_validating_a_latent_model_less_often_leaves_its_weights_as_they_were(recordings, tmp_path, monkeypatch):
    """The held-out loss is only reported: every fifth epoch and the last are validated, the others keep NaN, and
    the weights equal those of a run validated after every epoch."""
    import math

    import torch

    from softarm.learn import loop as training
    from softarm.learn.training import train
    from softarm.model.checkpoint import load_checkpoint

    config = load_config(overrides={**TINY, "train.epochs_ae": 2, "train.epochs_lstm": 7})
    sparse = load_checkpoint(train([recordings / "s0.mcap"], config, tmp_path / "sparse.pt").checkpoint)
    monkeypatch.setattr(training, "VALIDATE_EVERY", 1)
    every = load_checkpoint(train([recordings / "s0.mcap"], config, tmp_path / "every.pt").checkpoint)
    for network in ("autoencoder", "latent_model"):  # weights and the batch normalisation's running statistics
        assert all(torch.equal(every[network][key], value) for key, value in sparse[network].items())
    validated = [k for k, value in enumerate(sparse["losses"]["latent_val"]) if not math.isnan(value)]
    assert validated == [4, 6] and not any(map(math.isnan, every["losses"]["latent_val"]))
    assert ([sparse["losses"]["latent_val"][k] for k in validated]
            == [every["losses"]["latent_val"][k] for k in validated])
