"""Sensor imperfections on known signals: each has the configured statistics, they are seeded and
independent of each other, and the ideal model changes nothing."""


import numpy as np
import pytest

from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.sense.imperfections import SensorModel

RATE = 100.0  # Hz
T = 200_000
TIMES = np.arange(T) / RATE
SINE = np.stack([0.01 * np.sin(2 * np.pi * f * TIMES) for f in (0.3, 1.1, 2.7)], axis=1)  # (T, 3) m


def model(**fields) -> SensorModel:
    return SensorModel(**{"noise": 0.0, "bias": 0.0, "drift": 0.0, "quantisation": 0.0, "dropout_sensor": -1,
                          "dropout_time": 0.0, "seed": 0, **fields})


def lag1_correlation(x: np.ndarray) -> float:
    x = x - x.mean()
    return float(np.dot(x[:-1], x[1:]) / np.dot(x, x))


def test_default_config_is_ideal_and_round_trips_as_plain_values():
    sensing = load_config(overrides={"sensing.noise": 0.001, "sensing.seed": 7}).sensing
    m = SensorModel.from_config(sensing)
    assert (m.noise, m.seed) == (0.001, 7) and not m.ideal
    assert SensorModel.from_config(load_config().sensing).ideal


def test_ideal_model_returns_an_exact_float64_copy():
    readings = SINE.astype(np.float32)
    out = model().apply(readings, TIMES)
    assert out.dtype == np.float64 and out is not readings
    assert np.array_equal(out, readings.astype(np.float64))


def test_white_noise_has_the_configured_sigma_zero_mean_and_no_memory():
    sigma = 0.002
    noise = model(noise=sigma).apply(np.zeros((T, 3)), TIMES)
    for s in range(3):
        assert abs(noise[:, s].std() / sigma - 1) < 0.02
        assert abs(noise[:, s].mean()) < 5 * sigma / np.sqrt(T)
        assert abs(lag1_correlation(noise[:, s])) < 5 / np.sqrt(T)


def test_noise_is_added_to_the_signal():
    out = model(noise=0.001).apply(SINE, TIMES)
    assert abs((out - SINE).std() / 0.001 - 1) < 0.02


def test_bias_is_a_constant_per_sensor_spread_as_configured():
    sigma, sensors = 0.003, 20_000
    out = model(bias=sigma).apply(np.zeros((5, sensors)), np.arange(5) / RATE)
    assert np.all(out == out[0])
    assert abs(out[0].std() / sigma - 1) < 0.03
    assert abs(out[0].mean()) < 5 * sigma / np.sqrt(sensors)


def test_bias_differs_between_sensors_and_between_seeds():
    a = model(bias=0.003, seed=1).apply(np.zeros((2, 3)), np.arange(2) / RATE)
    b = model(bias=0.003, seed=2).apply(np.zeros((2, 3)), np.arange(2) / RATE)
    assert len(set(a[0])) == 3 and not np.array_equal(a, b)


@pytest.mark.parametrize("start", [0.0, 5.0])
def test_drift_variance_grows_as_drift_squared_times_elapsed_time(start):
    drift, sensors, times = 0.001, 5000, start + np.arange(1001) / RATE  # 10 s, each sensor one realisation
    walk = model(drift=drift).apply(np.zeros((len(times), sensors)), times)
    assert np.all(walk[0] == 0)
    for k in (100, 400, 1000):  # 1 s, 4 s, 10 s after the first sample
        assert abs(walk[k].var() / (drift**2 * (times[k] - times[0])) - 1) < 0.1


def test_drift_increments_are_independent_with_variance_drift_squared_dt():
    drift, dt = 0.001, 1 / RATE
    steps = np.diff(model(drift=drift).apply(np.zeros((T, 3)), TIMES), axis=0)
    for s in range(3):
        assert abs(steps[:, s].var() / (drift**2 * dt) - 1) < 0.02
        assert abs(lag1_correlation(steps[:, s])) < 5 / np.sqrt(T)


def test_drift_follows_irregular_sample_times():
    drift, sensors = 0.002, 5000
    times = np.array([0.0, 0.01, 0.5, 0.51, 4.0])
    walk = model(drift=drift).apply(np.zeros((len(times), sensors)), times)
    for k in range(1, len(times)):
        assert abs(walk[k].var() / (drift**2 * times[k]) - 1) < 0.1


def test_quantised_readings_are_multiples_of_the_step_within_half_a_step():
    step = 0.0005
    out = model(quantisation=step).apply(SINE, TIMES)
    units = out / step
    assert np.all(np.abs(units - np.round(units)) < 1e-9)
    assert np.all(np.abs(out - SINE) <= step / 2 * (1 + 1e-12))
    assert len(np.unique(out[:, 0])) == 2 * round(0.01 / step) + 1


def test_dropped_sensor_keeps_its_last_reading_and_the_others_are_untouched():
    out = model(dropout_sensor=1, dropout_time=10.0).apply(SINE, TIMES)
    start = 1000  # the first sample at 10 s
    assert np.all(out[start:, 1] == SINE[start - 1, 1])
    assert np.array_equal(out[:start, 1], SINE[:start, 1])
    assert np.array_equal(out[:, [0, 2]], SINE[:, [0, 2]])


def test_dropout_holds_the_imperfect_reading():
    noisy = model(noise=0.001, seed=3).apply(SINE, TIMES)
    out = model(noise=0.001, seed=3, dropout_sensor=2, dropout_time=0.505).apply(SINE, TIMES)
    assert np.all(out[51:, 2] == noisy[50, 2])
    assert np.array_equal(out[:51], noisy[:51]) and np.array_equal(out[:, :2], noisy[:, :2])


def test_dropout_at_or_before_the_first_sample_holds_the_first_reading():
    out = model(dropout_sensor=0, dropout_time=0.0).apply(SINE[100:], TIMES[100:])
    assert np.all(out[:, 0] == SINE[100, 0])


def test_dropout_after_the_last_sample_changes_nothing():
    out = model(dropout_sensor=0, dropout_time=TIMES[-1] + 1).apply(SINE, TIMES)
    assert np.array_equal(out, SINE)


def test_dropout_of_a_sensor_that_is_not_read_is_refused_naming_the_key():
    with pytest.raises(ConfigError, match="sensing.dropout_sensor") as e:
        model(dropout_sensor=3).apply(SINE[:10], TIMES[:10])
    assert "\n" not in str(e.value)


def test_same_seed_and_stream_give_the_same_readings_others_differ():
    full = model(noise=0.001, bias=0.001, drift=0.001, quantisation=1e-5, seed=4)
    readings, times = SINE[:1000], TIMES[:1000]
    out = full.apply(readings, times, stream=2)
    assert np.array_equal(out, full.apply(readings, times, stream=2))
    assert not np.array_equal(out, full.apply(readings, times, stream=3))
    assert not np.array_equal(out, model(noise=0.001, bias=0.001, drift=0.001, quantisation=1e-5, seed=5)
                              .apply(readings, times, stream=2))


def test_each_imperfection_keeps_its_realisation_when_another_is_switched_on():
    zeros, times = np.zeros((2000, 3)), TIMES[:2000]
    alone = {key: model(**{key: 0.001}, seed=9).apply(zeros, times, stream=1) for key in ("bias", "drift", "noise")}
    together = model(bias=0.001, drift=0.001, noise=0.001, seed=9).apply(zeros, times, stream=1)
    np.testing.assert_allclose(together, sum(alone.values()), rtol=0, atol=1e-15)
    drift_with_noise = model(drift=0.001, noise=0.001, seed=9).apply(zeros, times, stream=1)
    np.testing.assert_allclose(drift_with_noise - alone["noise"], alone["drift"], rtol=0, atol=1e-15)
