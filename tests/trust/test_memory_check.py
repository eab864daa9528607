"""The memory check against a system whose answer is known: a linear map from a state and the next command to the
felt signal, plus white noise of a known spread; and the surprise's reader, which carries it, against the batch."""

from dataclasses import replace

import numpy as np

from softarm.trust.surprise_fit import Piece, fit_memory_check, fit_surprise

MIX = np.array([[1.0, -0.5], [0.3, 0.2], [0.0, 1.0], [0.7, 0.0], [-0.2, 0.4]])


def state_world(seed: int, length: int = 6000, noise: float = 0.1):
    """States (T, 5), inputs (T, 3): two felt columns made from the state before and the command now, one command."""
    rng = np.random.default_rng(seed)
    states = rng.standard_normal((length, 5))
    command = rng.standard_normal(length)
    felt = np.zeros((length, 2))
    felt[1:] = states[:-1] @ MIX + command[1:, None] * [0.5, -1.0] + 0.3 + noise * rng.standard_normal((length - 1, 2))
    return states, np.column_stack([felt, command])


def test_the_memory_check_recovers_the_map_and_the_noise_spread_without_disturbed_samples():
    states, inputs = state_world(0)
    calm = np.ones(len(inputs), bool)
    spoiled = inputs.copy()
    spoiled[2000:4000, :2] += 5.0
    calm[2000:4000] = False
    check = fit_memory_check([(states, spoiled, calm)], [0, 1], [2], [state_world(1) + (np.ones(6000, bool),)])
    np.testing.assert_allclose(check.weights[:5], MIX, atol=0.01)
    np.testing.assert_allclose(check.weights[5:], [[0.5, -1.0], [0.3, 0.3]], atol=0.02)
    np.testing.assert_allclose(check.scale, [0.1, 0.1], rtol=0.05)
    residuals = check.residuals(*state_world(2))
    assert np.isnan(residuals[0]) and abs(np.nanmean(residuals) - 1.0) < 0.05  # chi-square per sensor: mean 1


def test_the_reader_gives_the_batch_series_of_both():
    states, inputs = state_world(0, 2000)
    calm = np.ones(len(inputs), bool)
    halves = [Piece(inputs[a:b], calm[a:b], calm[a:b], f"half {a}") for a, b in ((0, 1000), (1000, 2000))]
    model = fit_surprise(halves, [0, 1], [2], 0.01, 1.0)
    model = replace(model, memory=fit_memory_check([(states, inputs, calm)], [0, 1], [2], [(states, inputs, calm)]))
    test_states, test_inputs = state_world(3, 400)
    reader = model.online()
    online = [reader.step(x, s) for x, s in zip(test_inputs, test_states)]
    batch = model.series(test_inputs, test_states)
    np.testing.assert_allclose(np.array(online).T, batch, rtol=1e-9)
    assert np.isfinite(batch[1][1:]).all() and abs(np.mean(batch[1][1:]) - 1.0) < 0.2
