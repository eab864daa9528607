"""The top row's horizontal drive f(t + t0) = A * prod_i sin(2 pi f_i (t + t0)), and per-arm draws.

Arms of a batch differ only by their seed: arm i of a run with seed s uses seed s + i, so a batch arm
is the same run as a single-arm run with that seed. Seed 0 is the paper's run (t0 and A as
configured); every other seed draws t0 (and, with amplitude_jitter, A) from its own generator.
"""

from dataclasses import dataclass

import numpy as np

from softarm.config import ExcitationConfig


@dataclass(frozen=True)
class Drive:
    amplitude: float               # m
    frequencies: tuple[float, ...]  # Hz
    time_offset: float             # s, t0

    def displacement(self, t: np.ndarray) -> np.ndarray:
        """f(t + t0), m."""
        phase = 2 * np.pi * np.multiply.outer(np.asarray(t, float) + self.time_offset, self.frequencies)
        return self.amplitude * np.prod(np.sin(phase), axis=-1)

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """f'(t + t0), m/s: the product rule over the sine factors."""
        omega = 2 * np.pi * np.asarray(self.frequencies)
        phase = np.multiply.outer(np.asarray(t, float) + self.time_offset, omega)
        s, c = np.sin(phase), np.cos(phase)
        total = np.zeros(np.shape(t))
        for i in range(len(omega)):
            total = total + omega[i] * c[..., i] * np.prod(np.delete(s, i, axis=-1), axis=-1)
        return self.amplitude * total


def drive_for_seed(excitation: ExcitationConfig, seed: int) -> Drive:
    """The drive of the arm with this seed (seed 0: exactly as configured)."""
    amplitude, offset = excitation.amplitude, excitation.time_offset
    if seed != 0:
        rng = np.random.default_rng(seed)
        offset += float(rng.uniform(0.0, excitation.offset_range))
        amplitude *= float(rng.uniform(1 - excitation.amplitude_jitter, 1 + excitation.amplitude_jitter))
    return Drive(amplitude=amplitude, frequencies=tuple(excitation.frequencies), time_offset=offset)
