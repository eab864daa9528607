"""The privileged node ridge: its windows, its fit (against NumPy's least squares on the same windows), its answers."""

import numpy as np

from softarm.model import node_ridge


def test_windows_end_lead_samples_before_their_frame_and_start_padded_with_zeros():
    x = np.arange(1.0, 11.0)[:, None]  # samples 0..9 read 1..10
    w = node_ridge.windows(x, np.array([0, 1, 9]), lead=1)
    assert w.shape == (3, node_ridge.HISTORY)
    assert np.all(w[0] == 0)  # frame 0 has no sample before it
    assert w[1, -1] == 1.0 and np.all(w[1, :-1] == 0)
    assert np.array_equal(w[2, -9:], np.arange(1.0, 10.0))


def test_the_fit_solves_the_ridge_normal_equations_of_every_strided_training_frame():
    rng = np.random.default_rng(0)
    series = []
    for length, end in ((700, 600), (500, 450)):
        x = rng.normal(size=(length, 2))
        positions = rng.normal(size=(length, 3, 2))
        series.append((x, positions, end))
    weights, bias = node_ridge.fit(series, lead=1)
    rows, targets = [], []
    for x, p, end in series:
        frames = np.arange(1, end, node_ridge.STRIDE)
        rows.append(node_ridge.windows(x, frames, 1))
        targets.append(p[frames].reshape(len(frames), -1))
    X, Y = np.concatenate(rows), np.concatenate(targets)
    Xc, Yc = X - X.mean(0), Y - Y.mean(0)
    expected = np.linalg.solve(Xc.T @ Xc + node_ridge.ALPHA * len(X) * np.eye(X.shape[1]), Xc.T @ Yc)
    np.testing.assert_allclose(weights, expected, rtol=1e-6, atol=1e-10)
    np.testing.assert_allclose(bias, Y.mean(0) - X.mean(0) @ expected, rtol=1e-6, atol=1e-10)
    predicted = node_ridge.predict((weights, bias), series[0][0], np.array([5, 6]), lead=1)
    assert predicted.shape == (2, 3, 2)
