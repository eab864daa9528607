"""Tiny end-to-end trainings (seconds): learning happens, checkpoints reload safely, resume is exact."""

import json

import numpy as np
import pytest
import torch

from softarm.config import load_config
from softarm.imagine.imaginer import Imaginer
from softarm.learn.training import train
from softarm.model.checkpoint import load_checkpoint
from softarm.model.scaler import Scaler
from tests.helpers.cli import assert_one_line_error, softarm
from tests.helpers.tiny import TINY


def test_training_learns_and_beats_the_mean_frame(tiny_checkpoint):
    trained = tiny_checkpoint
    assert trained.complete
    state = load_checkpoint(trained.checkpoint)
    losses = state["losses"]
    assert losses["ae_train"][-1] < 0.5 * losses["ae_train"][0]
    assert losses["latent_train"][-1] < losses["latent_train"][0]
    m = trained.metrics
    assert m["counts"] == {**m["counts"], "train_frames": 340, "test_frames": 40, "imagination_predictions": 14}
    assert m["inputs"] == ["stretch"]  # a few recordings: the paper's model
    assert m["autoencoder_test"]["iou"] > 0.8
    model, mean = m["imagination"]["model"], m["imagination"]["mean_frame"]
    assert model["iou"] > mean["iou"] and model["bce"] < mean["bce"]
    assert json.loads(trained.metrics_path.read_text()) == json.loads(json.dumps(m))


def test_checkpoint_loads_with_weights_only_and_rebuilds_the_imaginer(tiny_checkpoint):
    trained = tiny_checkpoint
    state = torch.load(trained.checkpoint, weights_only=True)
    imaginer = Imaginer.from_checkpoint(state)
    assert state["recordings"][0]["name"] == "s0.mcap" and len(state["recordings"][0]["sha256"]) == 16
    assert (state["image_shape"] == [84, 52]
            and [(i["name"], i["features"]) for i in state["inputs"]] == [("stretch", 4)])
    stretch = np.random.default_rng(0).normal(0, 1e-3, (20, 4))
    prediction, probs = imaginer.imagine(stretch)
    assert prediction.targets.tolist() == list(range(6, 20)) and probs.shape == (14, 84, 52)
    assert probs.min() >= 0 and probs.max() <= 1
    assert ((prediction.confidence > 0) & (prediction.confidence <= 1)).all()


def test_feature_filter_drops_constant_features_and_normalisation_round_trips():
    rng = np.random.default_rng(1)
    data = rng.normal(3.0, 2.0, (500, 5))
    data[:, 2] = 7.0                      # constant: dropped
    data[:, 4] = 1.0 + 1e-6 * data[:, 4]  # nearly constant against the others: dropped
    scaler = Scaler.fit(data, min_relative_std=1e-3)
    assert scaler.keep.tolist() == [True, True, False, True, False]
    normalised = scaler.forward(data)
    assert np.allclose(normalised.mean(0), 0, atol=1e-12) and np.allclose(normalised.std(0), 1)
    back = scaler.inverse(normalised)
    assert np.allclose(back[:, scaler.keep], data[:, scaler.keep])
    assert np.allclose(back[:, ~scaler.keep], data[:, ~scaler.keep].mean(0), atol=1e-5)
    again = Scaler.from_state(scaler.to_state())
    assert np.array_equal(again.forward(data), normalised)


@pytest.mark.slow
def test_resume_after_an_interruption_ends_exactly_like_an_uninterrupted_run(recordings, tiny_checkpoint, tmp_path):
    trained = tiny_checkpoint
    out = tmp_path / "resumed.pt"
    config = load_config(overrides=TINY)
    batches = iter(range(10**6))
    first = train([recordings / "s0.mcap"], config, out, stop=lambda: next(batches) == 25)  # mid AE epoch 3
    assert not first.complete and first.metrics is None
    assert load_checkpoint(out)["progress"] == {"phase": "ae", "epoch": 2}
    second = train([recordings / "s0.mcap"], config, out, resume=True)
    assert second.complete
    assert second.metrics == trained.metrics
    np.testing.assert_equal(load_checkpoint(out)["losses"],
                            load_checkpoint(trained.checkpoint)["losses"])  # NaN: not validated


@pytest.mark.slow
def test_cli_refuses_recordings_that_do_not_fit_together(recordings, tmp_path):
    result = softarm("train", str(recordings / "s0.mcap"), str(recordings / "three_sensors.mcap"),
                     "--out", "x.pt", cwd=tmp_path)
    assert_one_line_error(result, "three_sensors.mcap", "3 stretch sensors", "4")
    assert not (tmp_path / "x.pt").exists()


@pytest.mark.parametrize("content, words", [(None, ["not found"]), (b"", ["empty"]), (b"hello world", ["not an MCAP"])])
def test_cli_refuses_missing_empty_and_foreign_recordings(tmp_path, content, words):
    if content is not None:
        (tmp_path / "r.mcap").write_bytes(content)
    assert_one_line_error(softarm("train", "r.mcap", "--out", "x.pt", cwd=tmp_path), "r.mcap", *words)
    assert not (tmp_path / "x.pt").exists()


def test_resume_warns_that_changed_settings_are_ignored(recordings, tiny_checkpoint, tmp_path):
    import shutil
    import warnings

    shutil.copy(tiny_checkpoint.checkpoint, tmp_path / "done.pt")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        again = train([recordings / "s0.mcap"], load_config(overrides={**TINY, "train.epochs_lstm": 99}),
                      tmp_path / "done.pt", resume=True)
    assert any("train.epochs_lstm = 99" in str(w.message) for w in caught)
    assert again.metrics == tiny_checkpoint.metrics  # the saved run was already finished: nothing changes


@pytest.mark.slow
def test_a_minutes_budget_shrinks_both_schedules_by_one_factor_and_is_kept_in_the_checkpoint(
        recordings, tmp_path, monkeypatch):
    from softarm.learn import budget, step_times
    from softarm.learn.loop import schedules
    from softarm.learn.train_state import start_state

    config = load_config(overrides={**TINY, "train.epochs_ae": 400, "train.epochs_lstm": 4000,  # hours of work
                                    "train.precision": "fp32"})
    monkeypatch.setattr(step_times, "autoencoder_steps", lambda state, asked: {"fp32": 0.01})  # measured, fixed here
    monkeypatch.setattr(step_times, "latent_steps", lambda state, asked: {"fp32": 0.001})
    state = start_state([recordings / "s0.mcap"], config, tmp_path / "x.pt", resume=False)
    ae, lstm = schedules(state)
    budget.fit_to_minutes(state, minutes=1.0, spent=6.0)
    scale = (60 * 0.9 - 6.0) / (ae.total * 0.01 + lstm.total * 0.001)
    assert state.config.train.max_steps_ae == int(ae.total * scale)
    assert state.config.train.max_steps_lstm == int(lstm.total * scale)
    monkeypatch.undo()  # the run below measures its own steps: the fixed times above would overrun its 6 s
    trained = train([recordings / "s0.mcap"], config, tmp_path / "budget.pt", minutes=0.1)
    saved = load_checkpoint(trained.checkpoint)["config"]["train"]
    assert trained.complete and 0 < saved["max_steps_ae"] < ae.total and 0 < saved["max_steps_lstm"] < lstm.total


@pytest.mark.slow
def test_the_work_before_and_after_the_steps_reports_its_progress(recordings, tiny_checkpoint, tmp_path):
    import shutil

    shutil.copy(tiny_checkpoint.checkpoint, tmp_path / "done.pt")  # finished: a resume reads and fits again
    heard = []
    train([recordings / "s0.mcap"], load_config(overrides=TINY), tmp_path / "done.pt", resume=True,
          stages=lambda stage, done, total: heard.append((stage, done, total)))
    assert heard == [("reading", 0, 1), ("reading", 1, 1), *(("fitting", k, 4) for k in range(5))]
    shutil.copy(tiny_checkpoint.checkpoint, tmp_path / "again.pt")
    log = softarm("train", str(recordings / "s0.mcap"), "--out", "again.pt", "--resume", cwd=tmp_path).stdout
    lines = [line for line in log.splitlines() if line.startswith(("reading", "fitting"))]
    assert lines[0] == "reading: started, 1 recordings" and lines[-1].startswith("fitting: ended at 4 of 4 fits"), log
