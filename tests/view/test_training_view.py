"""TrainingView writes an .rrd that rerun itself accepts and reads back to what was logged (no viewer spawned)."""

import subprocess
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest
import rerun as rr

from softarm.view.training_view import TrainingView
from tests.helpers.cli import RERUN

TIMES = np.arange(5) * 0.04
LOSSES = {"ae_train": [0.9, 0.5, 0.3], "ae_test": [1.0, 0.7, 0.6]}


def frames(seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((len(TIMES), 84, 52))


@pytest.fixture(scope="module")
def rrd(tmp_path_factory) -> Path:
    """One short run: two loss curves and one held-out clip of 5 frames 84x52."""
    path = tmp_path_factory.mktemp("viz") / "x.rrd"
    view = TrainingView(rrd=path)
    for name, values in LOSSES.items():
        for step, value in enumerate(values):
            view.loss(name, step, value)
    view.clip(3, TIMES, frames(0) > 0.5, frames(1), frames(2))
    assert not path.exists() and path.with_name("x.rrd.part").exists(), "an open view writes only the .part"
    view.close()
    view.close()
    return path


def rows(path: Path, entity: str) -> pa.Table:
    """Every row the file holds for `entity`, read with rerun's own chunk reader."""
    chunks = [c.to_record_batch() for c in rr.chunk.RrdReader(path).store().stream() if c.entity_path == entity]
    return pa.Table.from_batches(chunks).sort_by("rerun.controls.RowId")


def test_closed_view_leaves_a_whole_rrd_and_no_part(rrd):
    assert rrd.is_file()
    assert list(rrd.parent.iterdir()) == [rrd]
    done = subprocess.run([RERUN, "rrd", "verify", rrd], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_rrd_holds_every_entity_it_was_given_and_the_blueprint(rrd):
    reader = rr.chunk.RrdReader(rrd)
    entities = reader.store().schema().entity_paths()
    for entity in ("/loss/ae_train", "/loss/ae_test", "/clip/truth", "/clip/reconstruction", "/clip/imagination"):
        assert entity in entities
    assert [b.application_id for b in reader.blueprints()] == ["softarm-train"]


def test_losses_read_back_at_their_steps(rrd):
    table = rows(rrd, "/loss/ae_train")
    assert table["step"].to_pylist() == [0, 1, 2]
    assert [v[0] for v in table["Scalars:scalars"].to_pylist()] == LOSSES["ae_train"]


def test_clip_reads_back_as_grayscale_bytes_on_both_timelines(rrd):
    for name, expected in (("truth", frames(0) > 0.5), ("imagination", frames(2))):
        table = rows(rrd, f"/clip/{name}")
        pixels = np.array([blob[0] for blob in table["Image:buffer"].to_pylist()], np.uint8)
        np.testing.assert_array_equal(pixels.reshape(expected.shape), np.round(expected * 255).astype(np.uint8))
        assert table["step"].to_pylist() == [3] * len(TIMES)
        seconds = table["clip_time"].cast(pa.int64()).to_numpy() / 1e9
        np.testing.assert_allclose(seconds, TIMES)


def test_training_view_continues_the_latent_models_losses_after_the_autoencoders_on_one_step_axis(tiny_checkpoint):
    """Every loss point of a real training sits at its optimisation step: the LSTM's curve starts where
    the autoencoder's ends, and each clip is logged at the step of the epoch that made it."""
    from tests.helpers.tiny import TINY

    rrd = tiny_checkpoint.checkpoint.with_name("tiny.rrd")
    ae_steps = rows(rrd, "/loss/ae_train")["step"].to_pylist()
    lstm_steps = rows(rrd, "/loss/latent_train")["step"].to_pylist()
    per_epoch = -(-340 // TINY["train.batch_ae"])  # 340 training frames in batches of 32
    assert ae_steps == [per_epoch * (e + 1) for e in range(TINY["train.epochs_ae"])]
    assert len(lstm_steps) == TINY["train.epochs_lstm"] and lstm_steps[0] > ae_steps[-1]
    assert lstm_steps == sorted(set(lstm_steps))
    clip_steps = set(rows(rrd, "/clip/imagination")["step"].to_pylist())
    assert clip_steps == {lstm_steps[9], lstm_steps[-1]}  # every 10th LSTM epoch and the last
