"""The stream model's training data: pieces cover every training sample once, warm up before they count,
and the schedule counts exactly the steps an epoch takes."""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.learn.dataset import Dataset, RunData
from softarm.learn.sequences import Piece, partition, pieces, scored_chunks, steps_per_epoch


def dataset(lengths: list[int], train_frames: list[int]) -> Dataset:
    runs = [RunData(name=f"r{n}", fingerprint="0" * 16, frames=np.zeros((t, 2, 2), np.uint8),
                    stretch=np.zeros((t, 3), np.float32), times=np.arange(t) * 0.01, bounds=(b, t))
            for n, (t, b) in enumerate(zip(lengths, train_frames))]
    return Dataset(runs)


@pytest.mark.parametrize("lead", [0, 1])
@pytest.mark.parametrize("streams", [1, 3, 8, 32])
def test_pieces_score_every_training_sample_exactly_once(streams, lead):
    data = dataset([500, 300, 420], [400, 250, 0])  # the last one is a held-out recording: nothing trains
    every = pieces(data, streams, warmup=20, lead=lead)
    per_recording = -(-streams // 2)  # two recordings train; no piece is shorter than its warm-up
    assert len(every) == sum(max(1, min(per_recording, (end - lead) // 20)) for end in (400, 250))
    assert all(p.end - p.scored >= 20 for p in every)
    for n, end in ((0, 400 - lead), (1, 250 - lead)):
        scored = np.concatenate([np.arange(p.scored, p.end) for p in every if p.recording == n])
        assert np.array_equal(np.sort(scored), np.arange(end))
    assert all(p.recording != 2 for p in every)
    assert all(p.start == max(0, p.scored - 20) for p in every)  # a warm-up of 20 samples, none before the start


def test_steps_per_epoch_counts_chunks_with_a_scored_sample():
    data = dataset([1000] * 3, [900] * 3)
    parts = partition(data, streams=6, warmup=100, lead=1)
    assert [len(part) for part in parts] == [6]
    # two pieces a recording, [0, 450) and [450, 899) read from 350: 549 samples side by side, 6 chunks
    assert scored_chunks(parts[0], 100) == 6 == steps_per_epoch(data, 6, 100, 100, 1)
    assert scored_chunks([Piece(0, 0, 200, 300)], 100) == 1  # two chunks of warm-up only: read, not stepped
    assert len(partition(data, streams=2, warmup=100, lead=1)) == 2  # 3 pieces in groups of about 2


def test_one_epoch_of_the_stream_model_takes_the_steps_its_schedule_counts(recordings, tmp_path):
    from softarm.learn.train import schedules, stream_steps
    from softarm.learn.train_state import start_state

    config = load_config(overrides={"train.model": "stream", "train.streams": 5, "train.sequence": 40,
                                    "train.latent": 4, "train.lstm_hidden": 8})
    state = start_state([recordings / "s0.mcap", recordings / "s1.mcap"], config, tmp_path / "x.pt", resume=False)
    state.phase = "lstm"
    from softarm.learn.train import fit_scalers
    state.make_lstm(*fit_scalers(state, state.codes()))
    _, lstm = schedules(state)
    steps = list(stream_steps(state)(0))
    assert len(steps) == lstm.steps_per_epoch > 0
    loss, reported, items = steps[0]()
    assert loss.requires_grad and np.isfinite(reported) and items > 0
