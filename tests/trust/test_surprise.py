"""The surprise's forward model against systems whose answer is known: a lagged linear map from past inputs and the
next command to the felt signal (and a product of the newest sample), plus white noise of a known spread, steady or
growing with the motion's vigour; the novelty against its expectation; and the streamer's reader against the batch
series."""

import io

import numpy as np
import pytest
import torch

from softarm.model.device import on_cpu
from softarm.trust import correction
from softarm.trust.alarm import alarm_onsets, alarm_threshold
from softarm.trust.surprise import LAGS, SMOOTHING, WARM, SurpriseModel, linear_width, smoothed, vigour_signals
from softarm.trust.surprise_fit import Piece, fit_surprise

DT = 0.01
FELT, COMMAND = [0, 1], [2]


@pytest.fixture(autouse=True)
def brief_correction(monkeypatch):
    """These worlds are a lagged map and its products, which the ridge holds: a brief fit of the correction (on
    them it learns the noise's nothing) keeps each fit to seconds; test_correction fits it in full."""
    monkeypatch.setattr(correction, "EPOCHS", 4)


def linear_world(seed: int, length: int = 6000, noise=0.1, command_scale=None, product: float = 0.0,
                 power: int = 2):
    """Inputs (T, 3): two felt columns made from the two samples before and the command now, one command column;
    `noise` a spread or (T,) spreads, `command_scale` (T,) the command's size; `product` times the sample before's
    first felt column to the `power` added to the second."""
    rng = np.random.default_rng(seed)
    command = rng.standard_normal(length) * (1.0 if command_scale is None else command_scale)
    spread = np.broadcast_to(noise, (length,))
    felt = np.zeros((length, 2))
    for k in range(2, length):
        felt[k] = (felt[k - 1] @ [[0.5, 0.1], [-0.2, 0.3]] + felt[k - 2] @ [[-0.1, 0.0], [0.0, 0.2]]
                   + command[k - 1] * np.array([0.4, 0.0]) + command[k] * np.array([0.5, -1.0]) + 0.3
                   + np.array([0.0, product * felt[k - 1, 0] ** power]) + spread[k] * rng.standard_normal(2))
    return np.column_stack([felt, command])


def pieces(world, calm=None, fold: str = "world", blocks: int = 4, fitting: bool = True):
    """A world in `blocks` stretches of time, each a fold of its own, as a lone recording is fitted."""
    calm = np.ones(len(world), bool) if calm is None else calm
    edges = [len(world) * i // blocks for i in range(blocks + 1)]
    return [Piece(world[a:b], calm[a:b], np.full(b - a, fitting), f"{fold} {i}") for i, (a, b)
            in enumerate(zip(edges, edges[1:]))]


def fitted(*worlds, calibration=None, rate: float = 1.0):
    parts = [p for n, w in enumerate(worlds) for p in pieces(w, fold=f"world {n}")]
    if calibration is not None:
        parts += pieces(calibration, fold="held out", fitting=False)
    return fit_surprise(parts, FELT, COMMAND, DT, rate)


def world_map(world, product: float = 0.0):
    """(T - LAGS, 2) what the world's map makes of each sample from LAGS on, without its noise."""
    felt, command = world[:, :2], world[:, 2]
    k = np.arange(LAGS, len(world))
    return (felt[k - 1] @ [[0.5, 0.1], [-0.2, 0.3]] + felt[k - 2] @ [[-0.1, 0.0], [0.0, 0.2]]
            + command[k - 1, None] * [0.4, 0.0] + command[k, None] * [0.5, -1.0] + 0.3
            + np.column_stack([np.zeros(len(k)), product * felt[k - 1, 0] ** 2]))


def test_the_forward_model_recovers_the_map_and_the_noise_spread():
    model = fitted(linear_world(0, 30000), calibration=linear_world(1))
    test = linear_world(6)
    error = model.predicted(model.features(test)) - world_map(test)
    assert np.sqrt(np.mean(error ** 2)) < 0.01 and np.abs(error).max() < 0.04  # the noise is 0.1
    np.testing.assert_allclose(model.weights[3 * LAGS], [0.5, -1.0], atol=0.02)  # the next command's weight
    np.testing.assert_allclose(model.scale, [0.1, 0.1], rtol=0.05)
    surprise, memory = model.series(linear_world(2))
    assert np.isnan(surprise[WARM - 1]) and np.isfinite(surprise[WARM])  # silent until it is warm
    assert abs(np.nanmean(surprise) - 1.0) < 0.1  # chi-square per sensor over its expectation: mean 1
    assert np.isnan(memory).all()  # no memory check without the latent model's states


def test_the_expected_spread_follows_the_vigour_of_the_motion():
    """The felt noise grows tenfold while the command is large: the surprise stays about 1 in both regimes, where
    the residual over a single spread is far from 1 in each."""
    scale = np.where((np.arange(12000) // 1500) % 2 == 0, 0.1, 1.0)
    model = fitted(linear_world(0, 12000, noise=0.02 * scale / 0.1, command_scale=scale))
    test_scale = np.where((np.arange(6000) // 1500) % 2 == 0, 0.1, 1.0)
    world = linear_world(3, 6000, noise=0.02 * test_scale / 0.1, command_scale=test_scale)
    surprise = model.series(world)[0]
    plain = (model.residuals(world) ** 2).mean(axis=1)
    calm, vigorous = slice(200, 1500), slice(1700, 3000)  # after the averages have caught up
    assert 0.7 < np.mean(surprise[calm]) < 1.4 and 0.7 < np.mean(surprise[vigorous]) < 1.4
    assert np.mean(plain[vigorous]) / np.mean(plain[calm]) > 50


def test_a_push_the_command_did_not_predict_raises_the_alarm_at_once():
    model = fitted(linear_world(0), calibration=linear_world(1))
    pushed = linear_world(3)
    pushed[3000:3010, 0] += 1.0  # ten samples felt 10 sigma off
    surprise = model.series(pushed)[0]
    first = np.flatnonzero(surprise > model.threshold)
    assert len(first) and 3000 <= first[first >= 2990][0] <= 3001


def test_disturbed_frames_are_left_out_of_the_fit():
    spoiled = linear_world(0)
    spoiled[2000:4000, :2] += 5.0
    calm = np.ones(len(spoiled), bool)
    calm[2000:4000] = False
    clean = linear_world(1)
    model = fit_surprise([*pieces(spoiled, calm), *pieces(clean, fold="clean", fitting=False)], FELT, COMMAND, DT, 1.0)
    assert np.sqrt(np.mean((model.predicted(model.features(clean)) - world_map(clean)) ** 2)) < 0.02
    np.testing.assert_allclose(model.scale, [0.1, 0.1], rtol=0.05)


def test_without_two_folds_of_undisturbed_motion_there_is_no_surprise_to_fit():
    """Out of fold needs two folds to fit on: one disturbed throughout leaves the others to judge it; with one
    left, nothing can be judged, and the checkpoint goes without a surprise rather than a made-up one."""
    world = linear_world(0)
    disturbed = np.zeros(len(world), bool)
    parts = [*pieces(world, fold="calm", blocks=2), Piece(world, disturbed, np.ones(len(world), bool), "disturbed")]
    assert fit_surprise(parts, FELT, COMMAND, DT, 1.0) is not None
    assert fit_surprise([*pieces(world, fold="calm", blocks=1), parts[-1]], FELT, COMMAND, DT, 1.0) is None


def test_the_threshold_keeps_false_alarms_within_the_rate():
    rng = np.random.default_rng(5)
    series = [(smoothed(rng.chisquare(2, 6000) / 2), np.ones(6000, bool)) for _ in range(10)]  # 10 minutes
    for rate in (0.5, 2.0, 10.0):
        threshold = alarm_threshold(series, DT, rate)
        alarms = sum(len(alarm_onsets(s, threshold)) for s, _ in series)
        assert alarms <= rate * 10
        lower = threshold * 0.9  # and it is about the lowest that does
        assert sum(len(alarm_onsets(s, lower)) for s, _ in series) > alarms


def test_an_alarm_that_started_while_the_world_acted_is_no_false_alarm():
    """A minute of calm surprise about 1, with a poke every 3 s whose surprise of 50 decays over the 20 samples after
    it ends: those alarms began in the pokes, so the calm stretches after them start none, and the threshold stays
    at the calm surprise's own level; counted as starting in each stretch, they would set it near the decay's."""
    rng = np.random.default_rng(7)
    surprise = 1.0 + 0.1 * rng.standard_normal(6000)
    calm = np.ones(6000, bool)
    for start in range(150, 6000, 300):
        calm[start:start + 10] = False
        surprise[start:start + 10] = 50.0
        surprise[start + 10:start + 30] = 50.0 * 0.8 ** np.arange(1, 21)
    threshold = alarm_threshold([(surprise, calm)], DT, 1.0)
    assert threshold < 1.5
    assert calm[alarm_onsets(surprise, threshold)].sum() <= 1  # started in calm: within the rate of 1 a minute


def test_the_threshold_keeps_the_rate_at_every_threshold_above_it():
    """A minute of calm with one alarm-worthy swing that dips to 5.5 between two peaks of 10: below 5.5 it is one
    alarm (within one a minute), between 5.5 and 10 two. The lowest threshold within the rate would sit just above
    the calm level, where a slightly higher one already breaks the rate; the threshold is the lowest that holds at
    every threshold above it, the swing's peak."""
    rng = np.random.default_rng(3)
    surprise = 1.0 + 0.1 * rng.standard_normal(6000)
    surprise[3000:3040] = np.r_[np.linspace(2, 10, 10), np.linspace(10, 5.5, 10), np.linspace(5.5, 10, 10),
                                np.linspace(10, 2, 10)]
    series = [(surprise, np.ones(6000, bool))]
    threshold = alarm_threshold(series, DT, 1.0)
    assert len(alarm_onsets(surprise, 6.0)) == 2 and len(alarm_onsets(surprise, 2.5)) == 1  # the count is not monotone
    assert threshold >= 9.99 and len(alarm_onsets(surprise, threshold)) == 0


def test_an_arm_starting_to_move_sets_no_threshold():
    """Every piece starts with 30 samples the map does not hold (an arm starting from rest reads off its motion's
    expectation, at 20 noise spreads), left out of the forward model's fit but undisturbed. The surprise is silent
    until its averages and echoes are warm, so those starts raise no alarm the calibration counts and the threshold
    is no higher than without them (their vigour, still in the averages when it speaks, even lowers it). Spoken
    from the first prediction on, each piece's start would alarm, 8 in 2 minutes against the 2 allowed, and set
    the threshold at the starts' surprise (62 against 3.6)."""
    def starting(world, transient):
        edges = [len(world) * i // 4 for i in range(5)]
        out = []
        for i, (a, b) in enumerate(zip(edges, edges[1:])):
            piece = world[a:b].copy()
            piece[:30, FELT] += transient
            out.append(Piece(piece, np.ones(b - a, bool), np.arange(b - a) >= 30 + LAGS, f"world {a} {i}"))
        return out

    thresholds = [fit_surprise(starting(linear_world(0), t) + starting(linear_world(1), t), FELT, COMMAND, DT,
                               1.0).threshold for t in (0.0, 2.0)]
    assert thresholds[1] <= 1.05 * thresholds[0]


def test_smoothing_is_the_exponential_average_and_the_reader_equals_the_series():
    values = np.array([np.nan, 4.0, 1.0, np.nan, 7.0])
    a = 1 / SMOOTHING
    expected = [np.nan, 4.0, 4.0 + a * (1 - 4.0), 4.0 + a * (1 - 4.0), 0.0]
    expected[4] = expected[3] + a * (7.0 - expected[3])
    np.testing.assert_allclose(smoothed(values), expected)
    model = fitted(linear_world(0, 2000))
    inputs = linear_world(4, 500)
    reader = model.online()
    online = [reader.step(x) for x in inputs]
    np.testing.assert_allclose(np.array(online).T, model.series(inputs), rtol=1e-9)


def test_the_state_round_trips_and_an_earlier_kind_is_not_current():
    """What a checkpoint keeps (through torch's restricted loader) gives the same surprise back; a surprise of an
    earlier kind, or fitted without the innovation's echoes, is not read as this one."""
    model = fitted(linear_world(0, 2000))
    saved = io.BytesIO()
    torch.save(on_cpu(model.to_state()), saved)
    saved.seek(0)
    state = torch.load(saved, weights_only=True)
    world = linear_world(4, 500)
    np.testing.assert_allclose(SurpriseModel.from_state(state).series(world)[0], model.series(world)[0], rtol=1e-12)
    assert model.innovation is not None and SurpriseModel.current(state)
    assert not SurpriseModel.current({**state, "kind": "novelty"})
    assert not SurpriseModel.current({key: value for key, value in state.items() if key != "echoes"})
    assert not SurpriseModel.current({key: value for key, value in state.items() if key != "warm"})  # set cold


def noisier(world: np.ndarray, sigma: float, seed: int) -> np.ndarray:
    """The same motion read through sensors with `sigma` more white noise on the felt columns."""
    out = world.copy()
    out[:, FELT] += np.random.default_rng(seed).normal(0.0, sigma, (len(world), len(FELT)))
    return out


def test_noise_the_model_is_told_of_is_expected_not_surprising():
    """Sensors 0.3 (three times the fitted noise) noisier: the plain surprise reads about twenty; heard through that
    noise it is about 1 again, and the reader still equals the series."""
    model = fitted(linear_world(0, 12000), calibration=linear_world(1))
    world = noisier(linear_world(2), 0.3, 7)
    plain = np.nanmean(model.series(world)[0])
    told = model.heard_through(np.full(len(FELT), 0.3 ** 2))
    surprise = told.series(world)[0]
    assert plain > 8.0 and abs(np.nanmean(surprise) - 1.0) < 0.15
    reader = told.online()
    np.testing.assert_allclose([reader.step(x)[0] for x in world[:800]], surprise[:800], rtol=1e-9)
    assert not model.heard_through(np.zeros(len(FELT))).noise_floors(model.features(world)).any()


@pytest.mark.slow
def test_the_noise_terms_match_what_noise_adds_to_the_residuals_and_the_vigour():
    """Monte Carlo: the extra mean squared residual (in spreads) and the vigour signals' extra mean, from the same
    motion read with and without 0.2 of white noise, against the model's closed forms."""
    model = fitted(linear_world(0, 12000, product=0.3))
    assert abs(model.weights[3 * LAGS + 1, 1] - 0.3) < 0.04  # the product is the first one: felt 0 squared
    told = model.heard_through(np.full(len(FELT), 0.2 ** 2))
    clean = linear_world(5, 60000, product=0.3)
    noisy = noisier(clean, 0.2, 8)
    extra = (np.nanmean((told.residuals(noisy) ** 2).mean(axis=1))
             - np.nanmean((model.residuals(clean) ** 2).mean(axis=1)))
    assert abs(extra / np.mean(told.noise_floors(told.features(noisy)).mean(axis=1)) - 1.0) < 0.05
    bias = np.nanmean(model.residuals(noisy), axis=0) - np.nanmean(model.residuals(clean), axis=0)
    np.testing.assert_allclose(np.nanmean(told.residuals(noisy), axis=0) - np.nanmean(
        model.residuals(clean), axis=0), 0.0, atol=0.02)  # the products' bias taken off the prediction
    assert abs(bias[1]) > 0.05  # which, left on, is there
    added = np.nanmean(vigour_signals(noisy, model.felt, model.command), axis=0) - np.nanmean(
        vigour_signals(clean, model.felt, model.command), axis=0)
    np.testing.assert_allclose(added, told.inflation, rtol=0.05, atol=1e-3)


def test_the_novelty_is_the_mahalanobis_length_per_feature_about_one_on_the_motion_fitted():
    """The mean of x' M^-1 x over n features is 1 when M is the second moment of x: on the motion it was fitted on,
    the squared length per feature averages 1; on a motion with a command three times as large, far more."""
    model = fitted(linear_world(0, 30000))
    same = model.features(linear_world(1, 30000))
    larger = model.features(linear_world(2, 6000, command_scale=np.full(6000, 3.0)))
    assert abs(np.mean(np.exp(model.novelty(same)) - 1e-3) - 1.0) < 0.05
    assert np.mean(np.exp(model.novelty(larger))) > 4.0
    assert model.precision.shape == (linear_width(3, 1) + 1,) * 2


def test_the_threshold_is_set_out_of_fold_so_a_motion_no_fold_showed_stays_calm():
    """A world with a cubic term the forward model cannot hold, in two folds of small commands and one of large:
    the large fold, judged by the small folds' model, teaches the spread map what a new motion costs, and an
    unseen motion in between stays calm at the shipped threshold, where a model of the small folds alone, that
    never met a motion it did not know, raises alarm after alarm on it."""
    def world(seed, size):
        return linear_world(seed, 6000, product=0.02, power=3, command_scale=np.full(6000, size))

    small, large, unseen = [world(0, 0.5), world(1, 0.5)], world(2, 1.5), world(9, 1.2)
    spanning = fit_surprise([Piece(w, np.ones(len(w), bool), np.ones(len(w), bool), f"fold {n}")
                             for n, w in enumerate([*small, large])], FELT, COMMAND, DT, 1.0)
    narrow = fit_surprise([*pieces(small[0], fold="a"), *pieces(small[1], fold="b")], FELT, COMMAND, DT, 1.0)
    assert len(alarm_onsets(spanning.series(unseen)[0], spanning.threshold)) <= 1  # a minute of motion
    assert len(alarm_onsets(narrow.series(unseen)[0], narrow.threshold)) > 50
