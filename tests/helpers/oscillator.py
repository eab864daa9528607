"""One mass on one spring-damper: the body and the measurements that the analytic tests share.

Node 0 is held still (a drive of amplitude 0), node 1 hangs below it without gravity. Pulled along
the spring and let go, node 1 moves on the spring's line as y(t) = A e^(-zeta w0 t) cos(w_d t + phi)
with w0 = sqrt(k / m), zeta = b / (2 sqrt(k m)) and w_d = w0 sqrt(1 - zeta^2).
"""

import numpy as np

from softarm.arm.body import Body
from softarm.arm.drive import Drive

STIFFNESS, DAMPING, MASS, REST_LENGTH = 1000.0, 0.9, 0.01, 0.01
STILL = Drive(kind="product_of_sines", time_offset=0.0, direction=(1.0, 0.0), frequencies=(2.11, 3.73, 4.33),
              amplitude=0.0)


def one_spring(damping: float = DAMPING) -> Body:
    """Node 0 at the origin (driven, still), node 1 at rest REST_LENGTH below it; no gravity."""
    return Body(rest=np.array([[0.0, 0.0], [0.0, -REST_LENGTH]]), masses=np.full(2, MASS),
                springs=np.array([[0, 1]]), rest_lengths=np.array([REST_LENGTH]),
                stiffness=np.array([STIFFNESS]), damping=np.array([damping]), driven=np.array([0]),
                sensors=np.array([[0, 1]]), outline=np.array([0, 1, 0]), gravity=np.zeros(2))


def pulled(body: Body, stretch: float) -> np.ndarray:
    """Rest positions with node 1 moved `stretch` further along the spring (away from node 0)."""
    x = body.rest.copy()
    x[1, 1] -= stretch
    return x


def analytic_rates(damping: float = DAMPING) -> tuple[float, float]:
    """(w_d, zeta w0): the damped angular frequency and the amplitude's decay rate, 1/s."""
    w0 = np.sqrt(STIFFNESS / MASS)
    zeta = damping / (2 * np.sqrt(STIFFNESS * MASS))
    return w0 * np.sqrt(1 - zeta ** 2), zeta * w0


def measured_rates(t: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """(w_d, decay rate) of a sampled damped oscillation about 0.

    w_d from the mean spacing of the zero crossings (pi / w_d apart; linear interpolation between
    samples), the decay rate from a straight-line fit of log |y| at the extrema (pi / w_d apart, each
    e^(-zeta w0 pi / w_d) times the last; located by a parabola through the three samples around it).
    """
    dt = t[1] - t[0]
    k = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
    crossings = t[k] + dt * y[k] / (y[k] - y[k + 1])
    w_d = np.pi * (len(crossings) - 1) / (crossings[-1] - crossings[0])

    k = 1 + np.flatnonzero((np.abs(y[1:-1]) > np.abs(y[:-2])) & (np.abs(y[1:-1]) >= np.abs(y[2:])))
    a, b, c = np.abs(y[k - 1]), np.abs(y[k]), np.abs(y[k + 1])
    shift = 0.5 * (a - c) / (a - 2 * b + c)
    peak_times = t[k] + shift * dt
    peaks = b - 0.25 * (a - c) * shift
    decay = -np.polyfit(peak_times, np.log(peaks), 1)[0]
    return float(w_d), float(decay)
