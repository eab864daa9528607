/* softarm's physics as plain serial C: the benchmark's "practical limit of one core".

   The same model and scheme as `Simulator._advance` in softarm/sim/physics.py (docs/model.md, Forces and
   Integration): for each arm in turn, record the positions as a frame, then take `substeps`
   semi-implicit Euler steps to the next frame. One step:
     force = m g on every node, plus per spring (i, j): f = (k (L - L0) + b (v_j - v_i) . u) u on i, -f on j;
     free nodes:   v += h F / m,  then  x += h v  (with the new v);
     driven nodes: x = rest + (f(t), 0),  v = (f'(t), 0)  at the end of the step,
   with f(t) = A prod_n sin(2 pi freqs[n] t), t = (k substeps + s + 1) / substeps * frame_dt + t0.

   Arrays are row major, like the NumPy arrays of softarm: x, v, force (arms, nodes, 2),
   history (arms, n_frames, nodes, 2), pairs (springs, 2), rest (nodes, 2), per-arm amplitude and
   time_offset (arms). Unlike the Taichi kernel there is no blow-up check: a run that blows up just
   carries NaNs or huge numbers on, so only give it configurations the simulator accepts.
   Build: cc -O3 -march=native -shared -fPIC (bench/c_reference.py does it). */

#include <math.h>
#include <stddef.h>
#include <string.h>

static const double TWO_PI = 6.283185307179586;

/* (f(t), f'(t)) of the product of sines, by the product rule (softarm.sim.physics.product_of_sines). */
static inline void drive_at(double t, double amplitude, int n_freqs, const double *restrict freqs,
                            double *restrict value, double *restrict rate)
{
    double f = amplitude, df = 0.0;
    for (int n = 0; n < n_freqs; n++) {
        const double w = TWO_PI * freqs[n];
        const double s = sin(w * t), c = cos(w * t);
        df = df * s + f * w * c;
        f = f * s;
    }
    *value = f;
    *rate = df;
}

void advance(int arms, int nodes, int springs, const int *restrict pairs, const double *restrict rest_len,
             const double *restrict stiffness, const double *restrict damping, const double *restrict mass,
             const int *restrict free_, const double *restrict rest, double gx, double gy,
             const double *restrict amplitude, const double *restrict time_offset, int n_freqs,
             const double *restrict freqs, int first_frame, int n_frames, int substeps, double frame_dt,
             double *restrict x, double *restrict v, double *restrict force, double *restrict history)
{
    const double h = frame_dt / substeps;
    double h_over_mass[nodes];  /* h / m once, instead of a division per node and step */
    for (int i = 0; i < nodes; i++)
        h_over_mass[i] = h / mass[i];

    for (int a = 0; a < arms; a++) {
        double *restrict xa = x + (size_t)a * nodes * 2;
        double *restrict va = v + (size_t)a * nodes * 2;
        double *restrict fa = force + (size_t)a * nodes * 2;
        for (int f = 0; f < n_frames; f++) {
            memcpy(history + ((size_t)a * n_frames + f) * nodes * 2, xa, sizeof(double) * nodes * 2);
            const long frame = (long)first_frame + f;
            for (int s = 0; s < substeps; s++) {
                for (int i = 0; i < nodes; i++) {
                    fa[2 * i] = mass[i] * gx;
                    fa[2 * i + 1] = mass[i] * gy;
                }
                for (int e = 0; e < springs; e++) {
                    const int i = pairs[2 * e], j = pairs[2 * e + 1];
                    const double dx = xa[2 * j] - xa[2 * i], dy = xa[2 * j + 1] - xa[2 * i + 1];
                    const double length = sqrt(dx * dx + dy * dy);
                    const double inverse = 1.0 / length;
                    const double ux = dx * inverse, uy = dy * inverse;
                    const double rate = (va[2 * j] - va[2 * i]) * ux + (va[2 * j + 1] - va[2 * i + 1]) * uy;
                    const double magnitude = stiffness[e] * (length - rest_len[e]) + damping[e] * rate;
                    const double fx = magnitude * ux, fy = magnitude * uy;
                    fa[2 * i] += fx;
                    fa[2 * i + 1] += fy;
                    fa[2 * j] -= fx;
                    fa[2 * j + 1] -= fy;
                }
                const double t = (double)(frame * substeps + s + 1) / substeps * frame_dt + time_offset[a];
                double drive, drive_rate;
                drive_at(t, amplitude[a], n_freqs, freqs, &drive, &drive_rate);
                for (int i = 0; i < nodes; i++) {
                    if (free_[i]) {
                        va[2 * i] += h_over_mass[i] * fa[2 * i];
                        va[2 * i + 1] += h_over_mass[i] * fa[2 * i + 1];
                        xa[2 * i] += h * va[2 * i];
                        xa[2 * i + 1] += h * va[2 * i + 1];
                    } else {
                        xa[2 * i] = rest[2 * i] + drive;
                        xa[2 * i + 1] = rest[2 * i + 1];
                        va[2 * i] = drive_rate;
                        va[2 * i + 1] = 0.0;
                    }
                }
            }
        }
    }
}
