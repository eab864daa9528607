"""A stream model's training data: pieces cover every training sample once, warm up before they count,
and every model's schedule counts exactly the steps its epoch takes."""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.model.pieces import Piece, partition, pieces, scored_chunks, steps_per_epoch


@pytest.mark.parametrize("lead", [0, 1])
@pytest.mark.parametrize("streams", [1, 3, 8, 32])
def test_pieces_score_every_training_sample_exactly_once(streams, lead):
    train_ends = [400, 250, 0]  # of recordings of 500, 300 and 420 frames; the last one is held out: nothing trains
    every = pieces(train_ends, streams, warmup=20, lead=lead)
    per_recording = -(-streams // 2)  # two recordings train; no piece is shorter than its warm-up
    assert len(every) == sum(max(1, min(per_recording, (end - lead) // 20)) for end in (400, 250))
    assert all(p.end - p.scored >= 20 for p in every)
    for n, end in ((0, 400 - lead), (1, 250 - lead)):
        scored = np.concatenate([np.arange(p.scored, p.end) for p in every if p.recording == n])
        assert np.array_equal(np.sort(scored), np.arange(end))
    assert all(p.recording != 2 for p in every)
    assert all(p.start == max(0, p.scored - 20) for p in every)  # a warm-up of 20 samples, none before the start


def test_steps_per_epoch_counts_chunks_with_a_scored_sample():
    train_ends = [900] * 3
    parts = partition(train_ends, streams=6, warmup=100, lead=1)
    assert [len(part) for part in parts] == [6]
    # two pieces a recording, [0, 450) and [450, 899) read from 350: 549 samples side by side, 6 chunks
    assert scored_chunks(parts[0], 100) == 6 == steps_per_epoch(train_ends, 6, 100, 100, 1)
    assert scored_chunks([Piece(0, 0, 200, 300)], 100) == 1  # two chunks of warm-up only: read, not stepped
    assert len(partition(train_ends, streams=2, warmup=100, lead=1)) == 2  # 3 pieces in groups of about 2


@pytest.mark.parametrize("model", ["stream", "gru", "window"])
def test_one_epoch_of_a_latent_model_takes_the_steps_its_schedule_counts(recordings, tmp_path, model):
    from softarm.learn.loop import epoch_order, schedules
    from softarm.learn.train_state import start_state

    config = load_config(overrides={"train.model": model, "train.streams": 5, "train.sequence": 40,
                                    "train.latent": 4, "train.lstm_hidden": 8})
    state = start_state([recordings / "s0.mcap", recordings / "s1.mcap"], config, tmp_path / "x.pt", resume=False)
    state.phase = "latent"
    state.fit_scalers()
    state.make_latent()
    _, latent = schedules(state)
    steps = list(state.latent.epoch(state.training_series(), lambda n, e: epoch_order(n, 0, 1, e))(0))
    assert len(steps) == latent.steps_per_epoch > 0
    loss, reported, items = steps[0]()
    assert loss.requires_grad and np.isfinite(reported) and items > 0
