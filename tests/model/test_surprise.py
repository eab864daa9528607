"""The surprise's forward model against a system whose answer is known: a linear map from a state and a command
to the felt signal, plus white noise of a known spread; and the streamer's reader against the batch series."""

import numpy as np

from softarm.model.surprise import SMOOTHING, alarm_onsets, alarm_threshold, fit_surprise, smoothed

DT = 0.01


def linear_world(seed: int, length: int = 6000, noise: float = 0.1):
    """States (T, 5), inputs (T, 3): two felt columns made from the state before and the command now, one
    command column."""
    rng = np.random.default_rng(seed)
    states = rng.standard_normal((length, 5))
    command = rng.standard_normal(length)
    mix = np.array([[1.0, -0.5], [0.3, 0.2], [0.0, 1.0], [0.7, 0.0], [-0.2, 0.4]])
    felt = np.zeros((length, 2))
    felt[1:] = states[:-1] @ mix + command[1:, None] * [0.5, -1.0] + 0.3 + noise * rng.standard_normal((length - 1, 2))
    return states, np.column_stack([felt, command])


def test_the_forward_model_recovers_the_map_and_the_noise_spread():
    states, inputs = linear_world(0)
    calm = np.ones(len(inputs), bool)
    model = fit_surprise([(states, inputs, calm)], [0, 1], [2], [linear_world(1)[:2] + (calm,)], DT, 1.0)
    np.testing.assert_allclose(model.weights[:5], [[1.0, -0.5], [0.3, 0.2], [0.0, 1.0], [0.7, 0.0], [-0.2, 0.4]],
                               atol=0.01)
    np.testing.assert_allclose(model.weights[5:], [[0.5, -1.0], [0.3, 0.3]], atol=0.01)
    np.testing.assert_allclose(model.scale, [0.1, 0.1], rtol=0.05)
    surprise = model.series(*linear_world(2)[:2])
    assert np.isnan(surprise[0]) and abs(np.nanmean(surprise) - 1.0) < 0.05  # chi-square per sensor: mean 1


def test_a_push_the_command_did_not_predict_raises_the_alarm_at_once():
    states, inputs = linear_world(0)
    calm = np.ones(len(inputs), bool)
    model = fit_surprise([(states, inputs, calm)], [0, 1], [2], [linear_world(1)[:2] + (calm,)], DT, 1.0)
    test_states, test_inputs = linear_world(3)
    pushed = test_inputs.copy()
    pushed[3000:3010, 0] += 1.0  # ten samples felt 10 sigma off
    surprise = model.series(test_states, pushed)
    first = np.flatnonzero(surprise > model.threshold)
    assert len(first) and 3000 <= first[first >= 2990][0] <= 3001


def test_disturbed_frames_are_left_out_of_the_fit():
    states, inputs = linear_world(0)
    spoiled = inputs.copy()
    spoiled[2000:4000, :2] += 5.0
    calm = np.ones(len(inputs), bool)
    calm[2000:4000] = False
    model = fit_surprise([(states, spoiled, calm)], [0, 1], [2], [linear_world(1)[:2] + (np.ones(6000, bool),)], DT, 1.0)
    np.testing.assert_allclose(model.weights[-1], [0.3, 0.3], atol=0.02)


def test_the_threshold_keeps_false_alarms_within_the_rate():
    rng = np.random.default_rng(5)
    series = [(smoothed(rng.chisquare(2, 6000) / 2), np.ones(6000, bool)) for _ in range(10)]  # 10 minutes
    for rate in (0.5, 2.0, 10.0):
        threshold = alarm_threshold(series, DT, rate)
        alarms = sum(len(alarm_onsets(s, threshold)) for s, _ in series)
        assert alarms <= rate * 10
        lower = threshold * 0.9  # and it is about the lowest that does
        assert sum(len(alarm_onsets(s, lower)) for s, _ in series) > alarms


def test_smoothing_is_the_exponential_average_and_the_reader_equals_the_series():
    values = np.array([np.nan, 4.0, 1.0, np.nan, 7.0])
    a = 1 / SMOOTHING
    expected = [np.nan, 4.0, 4.0 + a * (1 - 4.0), 4.0 + a * (1 - 4.0), 0.0]
    expected[4] = expected[3] + a * (7.0 - expected[3])
    np.testing.assert_allclose(smoothed(values), expected)
    states, inputs = linear_world(0, 500)
    model = fit_surprise([(states, inputs, np.ones(500, bool))], [0, 1], [2], [(states, inputs, np.ones(500, bool))],
                         DT, 1.0)
    reader = model.online()
    online = [reader.step(s, x) for s, x in zip(states, inputs)]
    np.testing.assert_allclose(online, model.series(states, inputs), rtol=1e-9)
