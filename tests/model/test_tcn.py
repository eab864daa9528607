"""The causal convolution network: causal to the sample, memory of exactly its receptive field, rows that train on
the states the whole series gives, and a NumPy stream reader that answers as the batch pass."""

import numpy as np
import pytest
import torch

from softarm.config import load_config
from softarm.model.latent import TrainingSeries
from softarm.model.tcn import CausalTCN
from softarm.model.tcn.rows import ROW, cut, per_step, starts
from softarm.model.tcn.shape import RECEPTIVE


def _model(inputs: int = 3, width: int = 16) -> CausalTCN:
    torch.manual_seed(0)
    train = load_config(overrides={"train.lstm_hidden": width, "train.model": "tcn"}).train
    return CausalTCN(inputs, 5, train).eval()


def test_a_state_reads_its_sample_and_the_receptive_field_before_it_nothing_else():
    model = _model()
    series = np.random.default_rng(0).normal(size=(900, 3)).astype(np.float32)
    base = model.states(series)
    for k in (0, 300, 600):
        changed = series.copy()
        changed[k] += 0.5
        moved = np.abs(model.states(changed) - base).max(axis=1) > 1e-9
        assert not moved[:k].any()                       # causal: nothing before the change moves
        assert moved[k:k + RECEPTIVE].all()              # every state whose field holds the change moves
        assert not moved[k + RECEPTIVE:].any()           # memory ends with the receptive field


def test_the_layers_compute_what_a_plain_numpy_convolution_does():
    """An independent reference: each layer's dilated causal convolution as sums over its taps."""
    model = _model()
    series = np.random.default_rng(1).normal(size=(300, 3))
    x = series
    for i, (conv, dilation) in enumerate(zip(model.layers, (1, 2, 4, 8, 16, 32, 64, 128))):
        w, b = conv.weight.detach().double().numpy(), conv.bias.detach().double().numpy()
        padded = np.concatenate([np.zeros((dilation, x.shape[1])), x])
        y = np.maximum(padded[:-dilation] @ w[:, :, 0].T + padded[dilation:] @ w[:, :, 1].T + b, 0.0)
        x = y if i == 0 else x + y
    np.testing.assert_allclose(model.states(series.astype(np.float32)), x, atol=1e-4)


def test_the_stream_reader_answers_as_the_batch_pass_over_a_long_series():
    model = _model()
    series = np.random.default_rng(2).normal(size=(3000, 3)).astype(np.float32)
    batch = model.answer([series])[0]
    reader = model.online()
    streamed, states = {}, []
    for k, sample in enumerate(series):
        out = reader.step(sample)
        states.append(reader.state_vector)
        assert (out is None) == (k < model.history - 1)
        if out is not None:
            streamed[k + model.lead] = out
    np.testing.assert_allclose(np.stack(states), model.states(series), atol=2e-5)  # what the surprise reads
    assert sorted(streamed)[:len(batch.targets)] == list(batch.targets)
    np.testing.assert_allclose(np.stack([streamed[k][0] for k in batch.targets]), batch.latents, atol=2e-5)
    np.testing.assert_allclose(np.stack([streamed[k][1] for k in batch.targets]), batch.log_error, atol=2e-5)


def test_a_row_scores_the_states_the_whole_series_gives():
    model = _model()
    train = model.settings
    rng = np.random.default_rng(3)
    length = 2 * ROW + 300
    seen = rng.random(length) > 0.1
    series = TrainingSeries(rng.normal(size=(length, 3)).astype(np.float32),
                            rng.normal(size=(length, 5)).astype(np.float32), train_end=length - 50, seen=seen)
    rows = cut([series], train, RECEPTIVE, torch.device("cpu"))
    first = [f for _, f in starts([series.train_end], [seen], train.lead)]
    assert first == [0, ROW, 2 * ROW] and len(rows.samples) == 3
    whole = model.states(series.inputs)
    with torch.no_grad():
        states = model.features(rows.samples).double().numpy()
    for r, begin in enumerate(first):
        offset = min(begin, RECEPTIVE - 1)
        scored = np.flatnonzero(rows.scored[r].numpy())
        samples = scored - offset + begin
        assert samples.max() < series.train_end - train.lead and seen[samples + train.lead].all()
        np.testing.assert_allclose(states[r, scored], whole[samples], atol=1e-4)
        np.testing.assert_array_equal(rows.targets[r, scored].numpy(), series.latents[samples + train.lead])
    assert per_step(train) * ROW >= train.streams * train.sequence


@pytest.mark.parametrize("width", [8, 32])
def test_an_epoch_steps_as_often_as_it_says(width):
    model = _model(width=width)
    rng = np.random.default_rng(4)
    series = [TrainingSeries(rng.normal(size=(n, 3)).astype(np.float32), rng.normal(size=(n, 5)).astype(np.float32),
                             train_end=n - 10) for n in (700, 5000, 12000)]
    steps = list(model.epoch(series, lambda items, epoch: torch.randperm(items))(0))
    assert len(steps) == CausalTCN.steps_per_epoch([s.train_end for s in series], model.settings)
    loss, reported, items = steps[0]()
    assert loss.requires_grad and np.isfinite(reported) and items > 0
