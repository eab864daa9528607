"""`train.precision = "auto"`: settled once by timing both arithmetics on the run's own networks, the choice kept in
the checkpoint so that a resumed run continues in it."""

import pytest
import torch

from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.learn import precision, step_times
from softarm.learn.precision import forward_precision, has_bf16
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
    both = ("fp32", "bf16") if has_bf16(state.device) else ("fp32",)  # emulated bf16 has no LSTM (`require_native`)
    before = {k: v.clone() for k, v in state.autoencoder.state_dict().items()}
    for measured in (step_times.autoencoder_steps(state, both), step_times.latent_steps(state, both[-1:])):
        assert set(measured) <= {"fp32", "bf16"} and all(seconds > 0 for seconds in measured.values())
    after = state.autoencoder.state_dict()
    assert all(torch.equal(before[k], after[k]) for k in before)
    assert all(p.grad is None for p in state.autoencoder.parameters())


@pytest.mark.slow
def test_an_auto_training_keeps_its_choice_in_the_checkpoint(recordings, tmp_path, monkeypatch):
    chosen = "bf16" if has_bf16(torch.device("cpu")) else "fp32"  # the one this chip can train in, timed faster
    bf16 = 0.1 if chosen == "bf16" else 0.3
    timed(monkeypatch, {"fp32": 0.2, "bf16": bf16}, {"fp32": 0.2, "bf16": bf16})
    config = load_config(overrides={**TINY, "train.epochs_ae": 1, "train.epochs_lstm": 1, "train.precision": "auto"})
    assert config.train.precision == "auto"
    trained = train([recordings / "s0.mcap"], config, tmp_path / "auto.pt")
    assert load_checkpoint(trained.checkpoint)["config"]["train"]["precision"] == chosen


def test_bf16_on_a_chip_that_only_emulates_it_is_refused_before_any_step(recordings, tmp_path, monkeypatch):
    monkeypatch.setattr(precision, "has_bf16", lambda device: False)
    config = load_config(overrides={**TINY, "train.precision": "bf16"})
    with pytest.raises(ConfigError, match="natively.*\"fp32\""):
        train([recordings / "s0.mcap"], config, tmp_path / "bf16.pt")
    assert list(tmp_path.iterdir()) == []  # nothing written
    precision.require_native("fp32", torch.device("cpu"))  # fp32 runs anywhere


def test_auto_must_be_settled_before_a_step_runs():
    with pytest.raises(ValueError, match="fastest_precision"):
        forward_precision("auto")
