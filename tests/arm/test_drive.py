"""The drive of each excitation kind against closed forms written out independently (docs/model.md, Excitation)."""

import math

import numpy as np
import pytest

from softarm.arm.drive import Drive, drive_for_seed
from softarm.config import load_config

TIMES = np.linspace(0.0, 7.3, 2001)


def product_closed_form(t: float, amplitude: float, freqs: list[float], t0: float) -> tuple[float, float]:
    """A sin(a) sin(b) sin(c) and its derivative, expanded by hand for three factors."""
    (a, b, c), (wa, wb, wc) = [2 * math.pi * f * (t + t0) for f in freqs], [2 * math.pi * f for f in freqs]
    value = amplitude * math.sin(a) * math.sin(b) * math.sin(c)
    rate = amplitude * (wa * math.cos(a) * math.sin(b) * math.sin(c) + wb * math.sin(a) * math.cos(b) * math.sin(c)
                        + wc * math.sin(a) * math.sin(b) * math.cos(c))
    return value, rate


def sum_closed_form(t: float, amplitudes, freqs, phases, t0: float) -> tuple[float, float]:
    value = rate = 0.0
    for a, f, p in zip(amplitudes, freqs, phases):
        value += a * math.sin(2 * math.pi * f * (t + t0) + p)
        rate += a * 2 * math.pi * f * math.cos(2 * math.pi * f * (t + t0) + p)
    return value, rate


def central_difference(f, t: np.ndarray, h: float = 1e-6) -> np.ndarray:
    return (f(t + h) - f(t - h)) / (2 * h)


def test_product_of_sines_and_its_derivative_match_the_closed_form():
    drive = drive_for_seed(load_config().excitation, 3)
    expected = np.array([product_closed_form(t, drive.amplitude, list(drive.frequencies), drive.time_offset)
                         for t in TIMES])
    np.testing.assert_allclose(drive.displacement(TIMES), expected[:, 0], atol=1e-15)
    np.testing.assert_allclose(drive.velocity(TIMES), expected[:, 1], atol=1e-13)
    np.testing.assert_allclose(drive.velocity(TIMES), central_difference(drive.displacement, TIMES), atol=1e-7)


def test_sum_of_sines_and_its_derivative_match_the_closed_form():
    config = load_config(overrides={"excitation.kind": "sum_of_sines", "excitation.direction": [0.0, 1.0],
                                    "excitation.sum_of_sines.amplitudes": [0.002, 0.001, 0.0005],
                                    "excitation.sum_of_sines.frequencies": [0.4, 1.7, 3.1],
                                    "excitation.sum_of_sines.phases": [0.3, 2.0, -1.0]})
    drive = drive_for_seed(config.excitation, 4)
    assert drive.amplitudes == (0.002, 0.001, 0.0005) and drive.direction == (0.0, 1.0)
    expected = np.array([sum_closed_form(t, drive.amplitudes, drive.frequencies, drive.phases, drive.time_offset)
                         for t in TIMES])
    np.testing.assert_allclose(drive.displacement(TIMES), expected[:, 0], atol=1e-15)
    np.testing.assert_allclose(drive.velocity(TIMES), expected[:, 1], atol=1e-13)
    np.testing.assert_allclose(drive.velocity(TIMES), central_difference(drive.displacement, TIMES), atol=1e-7)


def band_config(**extra):
    return load_config(overrides={"excitation.kind": "sum_of_sines", "excitation.sum_of_sines.band": [0.5, 2.5],
                                  "excitation.sum_of_sines.components": 12, "excitation.sum_of_sines.rms": 0.003,
                                  **extra}).excitation


def test_a_band_draws_components_per_seed_at_the_asked_rms():
    excitation = band_config()
    drives = [drive_for_seed(excitation, seed) for seed in range(4)]
    for drive in drives:
        assert len(drive.frequencies) == 12 and all(0.5 <= f <= 2.5 for f in drive.frequencies)
        assert all(0 <= p < 2 * math.pi for p in drive.phases)
        t = np.arange(0.0, 2000.0, 0.01)
        assert np.sqrt(np.mean(drive.displacement(t) ** 2)) == pytest.approx(0.003, rel=0.03)
    assert len({d.frequencies for d in drives}) == 4  # every seed, seed 0 included, draws its own
    assert drive_for_seed(excitation, 2) == drives[2]  # and the same seed draws the same


def test_amplitude_jitter_scales_every_kind():
    for excitation in (band_config(**{"excitation.amplitude_jitter": 0.5}),
                       load_config(overrides={"excitation.amplitude_jitter": 0.5}).excitation):
        scales = {round(float(np.abs(drive_for_seed(excitation, s).displacement(TIMES)).max()), 6) for s in (1, 2, 3)}
        assert len(scales) == 3


def test_rhythm_jitter_scales_every_kinds_frequencies_by_the_seeds_third_draw():
    """The frequency scale is NumPy's third uniform draw of the seed (after t0 and the amplitude scale), so a seed's
    t0 and amplitude are those it drew before the key existed; seed 0 keeps the configured rhythm."""
    listed = {"excitation.kind": "sum_of_sines", "excitation.sum_of_sines.amplitudes": [0.001, 0.002],
              "excitation.sum_of_sines.frequencies": [0.7, 2.5], "excitation.sum_of_sines.phases": [0.0, 1.0]}
    for overrides, base in (({}, (2.11, 3.73, 4.33)), (listed, (0.7, 2.5))):
        excitation = load_config(overrides={**overrides, "excitation.rhythm_jitter": 0.3}).excitation
        steady = load_config(overrides=overrides).excitation
        assert drive_for_seed(excitation, 0).frequencies == base
        for seed in (1, 7, 123):
            draws = np.random.default_rng(seed).uniform(0.0, 1.0, 3)
            drive, before = drive_for_seed(excitation, seed), drive_for_seed(steady, seed)
            np.testing.assert_allclose(drive.frequencies, np.array(base) * (0.7 + 0.6 * draws[2]), rtol=1e-12)
            assert (drive.time_offset, drive.amplitude, drive.amplitudes) == (
                before.time_offset, before.amplitude, before.amplitudes)
            assert before.frequencies == base
    drawn = band_config(**{"excitation.rhythm_jitter": 0.3})
    factor = 0.7 + 0.6 * np.random.default_rng(4).uniform(0.0, 1.0, 3)[2]
    np.testing.assert_allclose(drive_for_seed(drawn, 4).frequencies,
                               np.array(drive_for_seed(band_config(), 4).frequencies) * factor, rtol=1e-12)


def test_metadata_names_exactly_the_parameters_of_the_kind():
    paper = drive_for_seed(load_config().excitation, 0).parameters()
    assert paper == {"kind": "product_of_sines", "time_offset": 0.0, "direction": [1.0, 0.0], "amplitude": 0.004,
                     "frequencies": [2.11, 3.73, 4.33]}
    multisine = drive_for_seed(band_config(), 1).parameters()
    assert set(multisine) == {"kind", "time_offset", "direction", "amplitudes", "frequencies", "phases"}
    rebuilt = Drive(**{k: tuple(v) if isinstance(v, list) else v for k, v in multisine.items()})
    np.testing.assert_array_equal(rebuilt.displacement(TIMES), drive_for_seed(band_config(), 1).displacement(TIMES))
