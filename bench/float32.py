"""How far the default run strays in float32 from float64: the NumPy reference's scheme (semi-implicit Euler, the
same forces) stepped in each precision over the whole 100 s run, the largest node difference reported as it grows.
The accuracy half of the question whether a float32 physics mode is worth having (the speed half needs a GPU).

    python -m bench.float32 [FRAMES]     # 10 000 frames (100 s) by default; about a minute and a half
"""

import sys
import time

import numpy as np

from softarm.config import load_config
from softarm.sim.batch import arm_batch


def run(dtype: type, frames: int) -> np.ndarray:
    """(frames, N, 2) node positions of the default run stepped in `dtype`."""
    config = load_config()
    b = arm_batch(config, seeds=[0])
    body, drive = b.body, b.drives[0]
    x, v = b.positions[0].astype(dtype), b.velocities[0].astype(dtype)
    i, j = body.springs[:, 0], body.springs[:, 1]
    free = np.ones(len(x), bool)
    free[body.driven] = False
    sub, dt = config.integration.substeps, config.integration.frame_dt
    h = dtype(dt / sub)
    L0, k, c = (a.astype(dtype) for a in (body.rest_lengths, body.stiffness, body.damping))
    m, g, rest = body.masses.astype(dtype), body.gravity.astype(dtype), body.rest.astype(dtype)
    out = np.empty((frames, len(x), 2))
    for f in range(frames):
        out[f] = x
        for s in range(sub):
            d = x[j] - x[i]
            L = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2)
            u = d / L[:, None]
            mag = k * (L - L0) + c * ((v[j] - v[i]) * u).sum(axis=1)
            fs = mag[:, None] * u
            F = np.zeros_like(x)
            np.add.at(F, i, fs)
            np.add.at(F, j, -fs)
            F += m[:, None] * g[None, :]
            v[free] += h * F[free] / m[free][:, None]
            x[free] += h * v[free]
            t = ((f * sub + s + 1) / sub) * dt
            x[body.driven] = rest[body.driven] + drive.along(float(drive.displacement(t))).astype(dtype)
            v[body.driven] = drive.along(float(drive.velocity(t))).astype(dtype)
    return out

def main() -> None:
    frames = int(sys.argv[1]) if len(sys.argv) > 1 else 10000
    start = time.time()
    gap = np.abs(run(np.float64, frames) - run(np.float32, frames)).max(axis=(1, 2))
    for seconds in (1, 10, 30, 60, 100):
        k = min(frames, int(seconds * 100)) - 1
        print(f"{seconds:>4} s: largest node difference float32 vs float64 so far {gap[:k + 1].max() * 1e3:.4f} mm")
    print(f"took {time.time() - start:.0f} s")


if __name__ == "__main__":
    main()
