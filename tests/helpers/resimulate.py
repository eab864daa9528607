"""A recording re-simulated from its metadata alone, by the equations of docs/model.md, written out again here
without softarm's code: the model document's nodes, masses, springs, drive, initial state and disturbances
are all it reads. If softarm's recording and this agree, the metadata says enough to re-simulate the run."""

import math
from typing import Any

import numpy as np


def drive(excitation: dict[str, Any]) -> tuple:
    """f(tau), f'(tau) of the metadata's excitation."""
    if excitation["kind"] == "product_of_sines":
        a, freqs = excitation["amplitude"], [2 * math.pi * f for f in excitation["frequencies"]]

        def f(tau: float) -> float:
            return a * math.prod(math.sin(w * tau) for w in freqs)

        def df(tau: float) -> float:
            return a * sum(w * math.cos(w * tau) * math.prod(math.sin(u * tau) for k, u in enumerate(freqs) if k != n)
                           for n, w in enumerate(freqs))
        return f, df
    parts = list(zip(excitation["amplitudes"], [2 * math.pi * f for f in excitation["frequencies"]],
                     excitation["phases"]))
    return (lambda tau: sum(a * math.sin(w * tau + p) for a, w, p in parts),
            lambda tau: sum(a * w * math.cos(w * tau + p) for a, w, p in parts))


def resimulate(model: dict[str, Any], frames: int) -> np.ndarray:
    """(frames, N, 2) node positions at t_k = k frame_dt."""
    x = np.array(model["initial"]["positions"], float)
    v = np.array(model["initial"]["velocities"], float)
    rest = np.array(model["nodes"], float)
    mass0 = np.array(model["masses"], float)
    springs = np.array(model["springs"], int)
    l0, k0, b = (np.array(model[key], float) for key in ("rest_lengths", "stiffness", "damping"))
    driven = np.array(model["driven"], int)
    free = np.setdiff1d(np.arange(len(x)), driven)
    g = np.array(model["gravity"], float)
    e = np.array(model["excitation"]["direction"], float)
    f, df = drive(model["excitation"])
    t0, dt, n = model["excitation"]["time_offset"], model["frame_dt"], model["substeps"]
    h = dt / n
    out = [x.copy()]
    for step in range((frames - 1) * n):
        frame, sub = divmod(step, n)
        t = (frame * n + sub) / n * dt  # the run time of the substep's start (docs/model.md)
        on = [d for d in model["disturbances"] if d["start"] <= t and (d["end"] is None or t < d["end"])]
        mass, k, push = mass0.copy(), k0.copy(), np.zeros_like(x)
        for d in on:
            if d["kind"] == "payload":
                mass[d["nodes"]] += d["mass"]
            elif d["kind"] == "stiffness":
                k[d["springs"]] *= d["factor"]
            elif d["kind"] == "push":
                push[d["nodes"]] += d["force"]
        force = mass[:, None] * g + push
        d = x[springs[:, 1]] - x[springs[:, 0]]
        length = np.hypot(d[:, 0], d[:, 1])
        u = d / length[:, None]
        pull = (k * (length - l0) + b * np.einsum("sk,sk->s", v[springs[:, 1]] - v[springs[:, 0]], u))[:, None] * u
        np.add.at(force, springs[:, 0], pull)
        np.add.at(force, springs[:, 1], -pull)
        for d in on:
            if d["kind"] == "obstacle":
                r = x[free] - d["centre"]
                distance = np.hypot(r[:, 0], r[:, 1])
                inside = (distance > 0) & (distance < d["radius"])
                normal = r[inside] / distance[inside, None]
                depth = d["radius"] - distance[inside]
                push_out = np.maximum(0.0, d["stiffness"] * depth
                                      - d["damping"] * np.einsum("nk,nk->n", v[free][inside], normal))
                force[free[inside]] += push_out[:, None] * normal
            elif d["kind"] == "drag":  # F = (c + c2 |w|) w, w = u - v, on every free node
                w = np.array(d["velocity"], float) - v[free]
                force[free] += (d["coefficient"] + d.get("quadratic", 0.0) * np.hypot(w[:, 0], w[:, 1]))[:, None] * w
        v[free] += h * force[free] / mass[free, None]
        x[free] += h * v[free]
        tau = (frame * n + sub + 1) / n * dt + t0
        x[driven] = rest[driven] + f(tau) * e
        v[driven] = df(tau) * e
        if (step + 1) % n == 0:
            out.append(x.copy())
    return np.array(out)
