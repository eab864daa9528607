"""The drive of the top row: f(t + t0) along a unit direction, in one of two closed forms, and per-arm draws.

`product_of_sines` (the paper): f = A prod_i sin(2 pi f_i tau). `sum_of_sines`: f = sum_i a_i
sin(2 pi f_i tau + phi_i), listed or drawn from a band (docs/model.md, Excitation). Arms of a batch
differ only by their seed: arm i of a run with seed s uses seed s + i, so a batch arm is the same run
as a single-arm run with that seed. Seed 0 takes t0, the amplitude and the rhythm as configured; every
other seed draws t0 (and, with amplitude_jitter and rhythm_jitter, an amplitude and a frequency scale)
from its own generator; with a band, every seed draws its components.
"""

from dataclasses import dataclass
from typing import Any

import numpy as np

from softarm.config import ExcitationConfig

PRODUCT, SUM = "product_of_sines", "sum_of_sines"
HELD_OUT_SEED_BASE = 1_000_000  # seeds from here on belong to the held-out suite: training refuses their recordings
KIND_CODES = {PRODUCT: 0, SUM: 1}  # how the Taichi kernel tells the kinds apart


@dataclass(frozen=True)
class Drive:
    kind: str
    time_offset: float                 # s, t0
    direction: tuple[float, float]     # unit vector e: the driven nodes move by f e
    frequencies: tuple[float, ...]     # Hz
    amplitude: float = 0.0             # product_of_sines: A, m
    amplitudes: tuple[float, ...] = ()  # sum_of_sines: a_i, m
    phases: tuple[float, ...] = ()      # sum_of_sines: phi_i, rad

    def displacement(self, t: np.ndarray) -> np.ndarray:
        """f(t + t0), m, along the direction."""
        tau = np.asarray(t, float) + self.time_offset
        if self.kind == SUM:
            return np.sin(self._sum_phase(tau)) @ np.asarray(self.amplitudes)
        phase = 2 * np.pi * np.multiply.outer(tau, self.frequencies)
        return self.amplitude * np.prod(np.sin(phase), axis=-1)

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """f'(t + t0), m/s, along the direction."""
        tau = np.asarray(t, float) + self.time_offset
        omega = 2 * np.pi * np.asarray(self.frequencies)
        if self.kind == SUM:
            return np.cos(self._sum_phase(tau)) @ (np.asarray(self.amplitudes) * omega)
        phase = np.multiply.outer(tau, omega)
        s, c = np.sin(phase), np.cos(phase)
        total = np.zeros(np.shape(t))
        for i in range(len(omega)):  # the product rule over the sine factors
            total = total + omega[i] * c[..., i] * np.prod(np.delete(s, i, axis=-1), axis=-1)
        return self.amplitude * total

    def along(self, value: float) -> np.ndarray:
        """value * e as an [x, y] vector; an axis the drive does not move gets exactly 0."""
        return np.array([value * e if e != 0.0 else 0.0 for e in self.direction])

    def _sum_phase(self, tau: np.ndarray) -> np.ndarray:
        return 2 * np.pi * np.multiply.outer(tau, self.frequencies) + np.asarray(self.phases)

    def parameters(self) -> dict[str, Any]:
        """The recording's excitation metadata: kind, t0, direction and the parameters of the kind."""
        out: dict[str, Any] = {"kind": self.kind, "time_offset": self.time_offset, "direction": list(self.direction)}
        if self.kind == SUM:
            out.update(amplitudes=list(self.amplitudes), frequencies=list(self.frequencies), phases=list(self.phases))
        else:
            out.update(amplitude=self.amplitude, frequencies=list(self.frequencies))
        return out


def drive_for_seed(excitation: ExcitationConfig, seed: int) -> Drive:
    """The drive of the arm with this seed (seed 0: t0, amplitude and frequencies exactly as configured)."""
    offset, scale, rhythm = excitation.time_offset, 1.0, 1.0
    if seed != 0:
        rng = np.random.default_rng(seed)
        offset += float(rng.uniform(0.0, excitation.offset_range))
        scale = float(rng.uniform(1 - excitation.amplitude_jitter, 1 + excitation.amplitude_jitter))
        rhythm = float(rng.uniform(1 - excitation.rhythm_jitter, 1 + excitation.rhythm_jitter))
    common = {"kind": excitation.kind, "time_offset": offset, "direction": tuple(excitation.direction)}
    if excitation.kind == PRODUCT:
        return Drive(**common, frequencies=tuple(f * rhythm for f in excitation.frequencies),
                     amplitude=excitation.amplitude * scale)
    sines = excitation.sum_of_sines
    if sines.amplitudes:
        return Drive(**common, frequencies=tuple(f * rhythm for f in sines.frequencies), phases=tuple(sines.phases),
                     amplitudes=tuple(a * scale for a in sines.amplitudes))
    drawn = multisine(sines.band, sines.components, sines.rms * scale, seed)
    return Drive(**common, **{**drawn, "frequencies": tuple(f * rhythm for f in drawn["frequencies"])})


def multisine(band: tuple[float, ...], components: int, rms: float, seed: int) -> dict[str, tuple[float, ...]]:
    """A random-phase multisine drawn from its own generator: frequencies uniform in the band (sorted),
    phases uniform in [0, 2 pi), amplitude weights uniform in [0.5, 1] scaled so that the RMS of the
    sum, sqrt(sum a_i^2 / 2) for distinct frequencies, is `rms`."""
    rng = np.random.default_rng((seed, 1))
    frequencies = np.sort(rng.uniform(band[0], band[1], components))
    phases = rng.uniform(0.0, 2 * np.pi, components)
    weights = rng.uniform(0.5, 1.0, components)
    amplitudes = weights * rms / np.sqrt(np.sum(weights ** 2) / 2)
    return {"frequencies": tuple(map(float, frequencies)), "phases": tuple(map(float, phases)),
            "amplitudes": tuple(map(float, amplitudes))}
