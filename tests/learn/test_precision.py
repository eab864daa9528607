"""`train.precision = "auto"`: settled once by timing both arithmetics on the run's own networks, the choice kept in
the checkpoint so that a resumed run continues in it."""

import pytest
import torch

from softarm.config import load_config
from softarm.learn import step_times
from softarm.learn.precision import forward_precision
from softarm.learn.train_state import start_state
from softarm.learn.training import train
from softarm.model.checkpoint import load_checkpoint
from tests.helpers.tiny import TINY


@pytest.fixture
def state(recordings, tmp_path):
    return start_state([recordings / "s0.mcap"], load_config(overrides=TINY), tmp_path / "x.pt", resume=False)


def timed(monkeypatch, ae: dict[str, float], latent: dict[str, float]) -> list[str]:
    """Step times fixed per precision; the precisions asked for, in order."""
    asked: list[str] = []
    monkeypatch.setattr(step_times, "has_bf16", lambda device: True)
    monkeypatch.setattr(step_times, "autoencoder_steps", lambda state, precisions: asked.extend(precisions) or ae)
    monkeypatch.setattr(step_times, "latent_steps", lambda state, precisions: latent)
    return asked


def test_bf16_is_chosen_only_where_it_speeds_up_both_networks_beyond_the_margin(state, monkeypatch):
    timed(monkeypatch, {"fp32": 0.10, "bf16": 0.08}, {"fp32": 0.01, "bf16": 0.008})
    assert step_times.fastest_precision(state) == "bf16"
    # the autoencoder faster in bf16, the latent model slower: fp32 (the Xeon without AMX)
    timed(monkeypatch, {"fp32": 0.10, "bf16": 0.08}, {"fp32": 0.010, "bf16": 0.014})
    assert step_times.fastest_precision(state) == "fp32"
    # within the margin, fp32's exact arithmetic is kept
    asked = timed(monkeypatch, {"fp32": 0.10, "bf16": 0.098}, {"fp32": 0.01, "bf16": 0.008})
    assert step_times.fastest_precision(state) == "fp32" and asked == ["fp32", "bf16"]


def test_without_native_bf16_nothing_is_timed(state, monkeypatch):
    asked = timed(monkeypatch, {"fp32": 1.0, "bf16": 0.01}, {"fp32": 1.0, "bf16": 0.01})
    monkeypatch.setattr(step_times, "has_bf16", lambda device: False)
    assert step_times.fastest_precision(state) == "fp32" and asked == []


def test_measuring_leaves_the_networks_as_they_were(state):
    before = {k: v.clone() for k, v in state.autoencoder.state_dict().items()}
    for measured in (step_times.autoencoder_steps(state, ("fp32", "bf16")), step_times.latent_steps(state, ("bf16",))):
        assert set(measured) <= {"fp32", "bf16"} and all(seconds > 0 for seconds in measured.values())
    after = state.autoencoder.state_dict()
    assert all(torch.equal(before[k], after[k]) for k in before)
    assert all(p.grad is None for p in state.autoencoder.parameters())


@pytest.mark.slow
def test_an_auto_training_keeps_its_choice_in_the_checkpoint(recordings, tmp_path, monkeypatch):
    timed(monkeypatch, {"fp32": 0.2, "bf16": 0.1}, {"fp32": 0.2, "bf16": 0.1})
    config = load_config(overrides={**TINY, "train.epochs_ae": 1, "train.epochs_lstm": 1, "train.precision": "auto"})
    assert config.train.precision == "auto"
    trained = train([recordings / "s0.mcap"], config, tmp_path / "auto.pt")
    assert load_checkpoint(trained.checkpoint)["config"]["train"]["precision"] == "bf16"


def test_auto_must_be_settled_before_a_step_runs():
    with pytest.raises(ValueError, match="fastest_precision"):
        forward_precision("auto")
