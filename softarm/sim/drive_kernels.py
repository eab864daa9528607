"""The excitation's closed forms as Taichi functions: (f(t), f'(t)) of every kind (docs/model.md, Excitation)."""

import taichi as ti


@ti.func
def product_of_sines(t: ti.f64, amplitude: ti.f64, a: int, freqs: ti.template()) -> ti.math.vec2:
    """(f(t), f'(t)) of A prod_i sin(w_i t), by the product rule."""
    value = amplitude
    rate = 0.0
    for n in range(freqs.shape[1]):
        w = 2.0 * ti.math.pi * freqs[a, n]
        s, c = ti.sin(w * t), ti.cos(w * t)
        rate = rate * s + value * w * c
        value = value * s
    return ti.Vector([value, rate], ti.f64)


@ti.func
def sum_of_sines(t: ti.f64, a: int, freqs: ti.template(), amps: ti.template(), phases: ti.template()) -> ti.math.vec2:
    """(f(t), f'(t)) of sum_i a_i sin(w_i t + phi_i)."""
    value = 0.0
    rate = 0.0
    for n in range(freqs.shape[1]):
        w = 2.0 * ti.math.pi * freqs[a, n]
        phase = w * t + phases[a, n]
        value += amps[a, n] * ti.sin(phase)
        rate += amps[a, n] * w * ti.cos(phase)
    return ti.Vector([value, rate], ti.f64)
