"""The forward model's correction against known answers: a smooth function it must learn, its gradient against
central differences of itself, its saved state, and a world whose felt signal is not a product of its inputs
(the correction takes what the ridge cannot, and the surprise's noise floor still matches what noise adds)."""

import numpy as np
import pytest

from softarm.trust.correction import Correction, fit_correction
from softarm.trust.surprise import LAGS
from softarm.trust.surprise_fit import Piece, fit_surprise

DT = 0.01


def smooth(x: np.ndarray) -> np.ndarray:
    return np.column_stack([np.sin(2.0 * x[:, 0]) * x[:, 1], np.tanh(x[:, 2] - x[:, 0])])


def test_the_network_learns_a_smooth_map_it_was_shown_and_applies_it_in_numpy():
    rng = np.random.default_rng(0)
    x, test = rng.standard_normal((20000, 3)), rng.standard_normal((2000, 3))
    correction = fit_correction(x, smooth(x))
    error = correction(test) - smooth(test)
    linear = np.c_[test, np.ones(len(test))] @ np.linalg.lstsq(np.c_[x, np.ones(len(x))], smooth(x), rcond=None)[0]
    assert np.sqrt(np.mean(error ** 2)) < 0.15 * smooth(test).std()
    assert np.sqrt(np.mean(error ** 2)) < 0.2 * np.sqrt(np.mean((linear - smooth(test)) ** 2))


def test_its_gradient_is_the_central_difference_of_its_answer_and_its_state_reloads_the_same():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((4000, 5))
    correction = fit_correction(x, smooth(x[:, 1:]))
    rows, h = rng.standard_normal((7, 5)), 1e-5
    columns = [0, 2, 4]
    numeric = np.stack([(correction(rows + h * np.eye(5)[c]) - correction(rows - h * np.eye(5)[c])) / (2 * h)
                        for c in columns], axis=1)
    np.testing.assert_allclose(correction.gradient(rows, columns), numeric, rtol=1e-5, atol=1e-8)
    reloaded = Correction.from_state(correction.to_state())
    np.testing.assert_array_equal(reloaded(rows), correction(rows))


def saturating_world(seed: int, length: int = 12000, noise: float = 0.02) -> np.ndarray:
    """Inputs (T, 2): a felt column driven through a saturation (tanh) of its past and the command, a command."""
    rng = np.random.default_rng(seed)
    command = np.sin(np.cumsum(rng.uniform(0.02, 0.2, length))) * rng.uniform(0.5, 2.0)
    felt = np.zeros(length)
    for k in range(2, length):
        felt[k] = (0.6 * felt[k - 1] - 0.2 * felt[k - 2] + np.tanh(2.0 * command[k] + felt[k - 1])
                   + noise * rng.standard_normal())
    return np.column_stack([felt, command])


@pytest.mark.slow
def test_the_correction_takes_what_the_ridge_leaves_and_the_noise_floor_matches_what_noise_adds():
    worlds = [saturating_world(seed) for seed in range(2)]
    model = fit_surprise([Piece(w, np.ones(len(w), bool), np.ones(len(w), bool), f"w{n}")
                          for n, w in enumerate(worlds)], [0], [1], DT, 1.0)
    test = saturating_world(7)
    features = model.features(test)
    error = test[LAGS:, 0] - model.predicted(features)[:, 0]
    ridge_only = test[LAGS:, 0] - features @ model.weights[:, 0]
    assert np.sqrt(np.mean(error ** 2)) < 0.6 * np.sqrt(np.mean(ridge_only ** 2))
    # white noise of a known variance on the felt column: the floor expects what it adds to the squared residual
    variance = 0.03 ** 2
    noisy = test.copy()
    noisy[:, 0] += np.random.default_rng(8).normal(0.0, np.sqrt(variance), len(test))
    heard = model.heard_through(np.array([variance]))
    added = np.mean(heard.residuals(noisy)[LAGS:] ** 2) - np.mean(model.residuals(test)[LAGS:] ** 2)
    floor = np.mean(heard.noise_floors(heard.features(noisy)).mean(axis=1))
    assert abs(added - floor) < 0.15 * floor
