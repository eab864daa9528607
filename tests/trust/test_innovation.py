"""The innovation against processes whose answer is known: errors that follow a first-order autoregression, whose
best one-step prediction is the coefficient times the error before and whose innovation has the spread of the
driving noise; white noise added to such errors, whose share of the innovation is the noise's variance through
every echo; and a step that the plain error hides in a persistent one."""

import numpy as np

from softarm.trust.innovation import ECHOES, echoes
from softarm.trust.scoring import auroc
from softarm.trust.surprise import DESIGN, LAGS
from softarm.trust.surprise_fit import fit_innovation

RHO = 0.8


def persistent(seed: int, length: int = 20000, sensors: int = 3) -> np.ndarray:
    """(T, P) errors e_k = RHO e_{k-1} + xi_k with unit variance (xi of variance 1 - RHO^2), NaN for the first LAGS
    samples as the forward model leaves them."""
    rng = np.random.default_rng(seed)
    xi = rng.normal(0.0, np.sqrt(1.0 - RHO ** 2), (length, sensors))
    out = np.zeros((length, sensors))
    out[0] = rng.standard_normal(sensors)
    for k in range(1, length):
        out[k] = RHO * out[k - 1] + xi[k]
    out[:LAGS] = np.nan
    return out


def constant_design(length: int) -> np.ndarray:
    design = np.zeros((length, DESIGN))
    design[:, -1] = 1.0
    return design


def fitted(*series):
    quiet = [np.arange(len(s)) >= LAGS for s in series]
    return fit_innovation(list(series), [constant_design(len(s)) for s in series], quiet)


def test_the_echoes_are_the_errors_before_newest_first_and_zero_before_the_first():
    errors = np.arange(24.0).reshape(12, 2)
    errors[:3] = np.nan
    lagged = echoes(errors)
    assert lagged.shape == (12, 2 * ECHOES)
    np.testing.assert_array_equal(lagged[5, :2], errors[4])
    np.testing.assert_array_equal(lagged[5, 2:4], errors[3])
    np.testing.assert_array_equal(lagged[5, 4:], 0.0)  # samples 2, 1, 0 made no prediction, and none before


def test_an_autoregression_is_recovered_and_its_innovation_has_the_driving_noise_spread():
    model = fitted(persistent(0), persistent(1))
    first = model.persistence[:3]
    np.testing.assert_allclose(first, RHO * np.eye(3), atol=0.02)
    older = model.persistence[3:]  # older echoes add nothing but the fit's noise
    assert np.sqrt(np.mean(older ** 2)) < 0.01 and np.abs(older).max() < 0.04
    np.testing.assert_allclose(model.scale, np.sqrt(1.0 - RHO ** 2), rtol=0.03)
    news = model.news(persistent(2))
    assert abs(np.nanmean(news ** 2) - 1.0) < 0.05
    lag_one = np.corrcoef(news[LAGS + 1:, 0], news[LAGS:-1, 0])[0, 1]
    assert abs(lag_one) < 0.03  # white, where the errors correlated 0.8


def test_white_noise_added_to_the_errors_is_expected_through_every_echo():
    """Half the error persistent, half white noise the model was not fitted with: the mean squared innovation (in
    its spreads) against `expected` with the motion's share 1/2 and the noise's 1/2 on every sensor."""
    model = fitted(persistent(0), persistent(1))
    rng = np.random.default_rng(4)
    errors = np.sqrt(0.5) * persistent(3, 60000) + np.sqrt(0.5) * rng.standard_normal((60000, 3))
    measured = np.nanmean((model.news(errors) ** 2).mean(axis=1))
    expected = model.expected(constant_design(1), np.array([0.5]), np.full((1, 3), 0.5))[0]
    assert abs(measured / expected - 1.0) < 0.03
    without = model.expected(constant_design(1), np.array([0.5]), np.zeros((1, 3)))[0]
    assert measured / without > 3.0  # the noise's share, left out, is most of it


def test_a_step_hidden_in_persistent_errors_stands_out_in_the_innovation():
    """Steps of one spread of the errors for 10 samples, every 200 samples: against the samples without one, the
    plain squared error ranks the steps' first samples weakly, the squared innovation far better (a first sample
    of 1 / sqrt(1 - RHO^2) = 1.7 of its spread)."""
    model = fitted(persistent(0), persistent(1))
    errors = persistent(5)
    stepped = np.zeros(len(errors), bool)
    for start in range(200, len(errors) - 20, 200):
        stepped[start:start + 10] = True
    errors[stepped] += 1.0
    onsets = stepped & ~np.roll(stepped, 1)
    kept = np.isfinite(errors).all(axis=1) & (onsets | ~stepped)
    plain = auroc((errors ** 2).mean(axis=1)[kept], onsets[kept])
    innovation = auroc((model.news(errors) ** 2).mean(axis=1)[kept], onsets[kept])
    assert innovation > 0.85 and innovation > plain + 0.1  # measured 0.91 against 0.72
