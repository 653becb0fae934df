/* The sampled loop of the time solutions (pedalrepro.integrator): whole runs in C with the
   Dormand-Prince 5(4) step of dopri.h and terminal fall events |x[i]| >= limit.

   The right-hand side is a function pointer with a context (a model's parameters and forcing),
   so one loop serves the non-linear models (model_library.c) and the linear models
   (linear_library.c). Two variants (dopri_options.variant):

   DOPRI_SCIPY   scipy.integrate.solve_ivp(method="RK45") step for step: its initial step
                 (Hairer's algorithm, select_initial_step), its step-size rules (safety 0.9,
                 factors 0.2..10, no growth right after a rejection, accept when err < 1), its
                 quartic dense output for the samples and the events (located on that
                 interpolant to round-off, as scipy's brentq at 4 eps).
   DOPRI_HERMITE the project's first compiled scheme, kept for the NT/NP sweeps so that their
                 tables stay byte-identical: a simplified initial step, cubic Hermite samples
                 between steps and events bisected on that interpolant.

   Both use the error norm of scipy: rms of err / (atol + rtol max(|y|, |y_new|)).       */
#ifndef PEDALREPRO_DOPRI_SAMPLED_H
#define PEDALREPRO_DOPRI_SAMPLED_H

#include "dopri.h"

#define DOPRI_SCIPY 0
#define DOPRI_HERMITE 1

typedef struct {
    double rtol, atol;
    int n_events;
    const int *event_index;       /* terminal events: |x[event_index[k]]| >= event_limit[k] */
    const double *event_limit;
    int variant;                  /* DOPRI_SCIPY or DOPRI_HERMITE */
    long max_steps;
} dopri_options;

/* One evaluation of a right-hand side (for callers that evaluate a model at a state). */
int dopri_eval(dopri_rhs f, const void *ctx, double t, const double *x, double *dx) {
    return f(ctx, t, x, dx);
}

static void dopri_hermite(int n, double t0, double t1, const double *y0, const double *y1,
                          const double *f0, const double *f1, double t, double *out) {
    double h = t1 - t0, s = (t - t0) / h, s2 = s * s, s3 = s2 * s;
    double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (int i = 0; i < n; i++) out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
}

/* scipy's RkDenseOutput: y(t) = y_old + h Q [x, x^2, x^3, x^4], x = (t - t_old) / h. */
static void dopri_quartic(int n, double t0, double h, const double *y0, const double *q,
                          double t, double *out) {
    double x = (t - t0) / h, p1 = x, p2 = p1 * x, p3 = p2 * x, p4 = p3 * x;
    for (int i = 0; i < n; i++)
        out[i] = y0[i] + h * (q[4 * i] * p1 + q[4 * i + 1] * p2 + q[4 * i + 2] * p3 + q[4 * i + 3] * p4);
}

static int dopri_event(const dopri_options *o, const double *y) {
    for (int k = 0; k < o->n_events; k++)
        if (fabs(y[o->event_index[k]]) >= o->event_limit[k]) return 1;
    return 0;
}

/* Returns 0 finished, 1 an event ended the run, negative on failure (-1 non-finite state or the
   right-hand side failed, -2 step size underflow, -3 too many steps, -4 bad arguments).
   out: n x n_t (row per state, NaN after an event). The run starts at t_out[0] from x0. */
int dopri_integrate(dopri_rhs f, const void *ctx, int n, const double *x0, const double *t_out,
                    int n_t, const dopri_options *o, double *out, double *t_end, long *n_rhs) {
    double y[DOPRI_NMAX], f0[DOPRI_NMAX], k2[DOPRI_NMAX], k3[DOPRI_NMAX], k4[DOPRI_NMAX];
    double k5[DOPRI_NMAX], k6[DOPRI_NMAX], k7[DOPRI_NMAX], yn[DOPRI_NMAX], tmp[DOPRI_NMAX];
    double yi[DOPRI_NMAX], q[4 * DOPRI_NMAX];
    double *const k[7] = {f0, k2, k3, k4, k5, k6, k7};
    if (n < 1 || n > DOPRI_NMAX || n_t < 1) return -4;
    const double rtol = o->rtol, atol = o->atol;
    const int scipy = o->variant == DOPRI_SCIPY;
    double t = t_out[0], tf = t_out[n_t - 1];
    for (int i = 0; i < n; i++) y[i] = x0[i];
    for (long j = 0; j < (long)n_t * n; j++) out[j] = NAN;
    *n_rhs = 0;
    *t_end = t;
    if (f(ctx, t, y, f0)) return -1;
    (*n_rhs)++;
    for (int i = 0; i < n; i++) out[i * n_t] = y[i];
    int next = 1;
    if (n_t == 1 || tf <= t) { *t_end = t; return 0; }
    /* initial step: Hairer's algorithm as scipy's select_initial_step (order 4) */
    double d0 = 0, d1 = 0;
    for (int i = 0; i < n; i++) { double sc = atol + rtol * fabs(y[i]); d0 += (y[i] / sc) * (y[i] / sc); d1 += (f0[i] / sc) * (f0[i] / sc); }
    d0 = sqrt(d0 / n); d1 = sqrt(d1 / n);
    double h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h > tf - t) h = tf - t;
    if (scipy) {
        for (int i = 0; i < n; i++) tmp[i] = y[i] + h * f0[i];
        if (f(ctx, t + h, tmp, k2)) return -1;
        (*n_rhs)++;
        double d2 = 0;
        for (int i = 0; i < n; i++) { double sc = atol + rtol * fabs(y[i]); double v = (k2[i] - f0[i]) / sc; d2 += v * v; }
        d2 = sqrt(d2 / n) / h;
        double h1 = (d1 <= 1e-15 && d2 <= 1e-15) ? fmax(1e-6, h * 1e-3)
                                                  : pow(0.01 / fmax(d1, d2), 1.0 / 5.0);
        double h0 = h;
        h = fmin(fmin(100 * h0, h1), tf - t);
    }
    long steps = 0;
    int rejected = 0;
    while (t < tf) {
        double t1;
        if (scipy) {
            double min_step = 10 * fabs(nextafter(t, INFINITY) - t);
            if (!rejected && h < min_step) h = min_step;   /* a new step starts at min_step */
            if (h < min_step) return -2;
            t1 = t + h;
            if (t1 > tf) t1 = tf;
            h = t1 - t;
        } else {
            if (h < 1e-12) return -2;
            if (t + h > tf) h = tf - t;
            t1 = t + h;
        }
        if (dopri_step(f, ctx, n, t, h, y, k, yn, tmp)) return -1;
        *n_rhs += 6;
        double err = 0;
        for (int i = 0; i < n; i++) {
            double sc = atol + rtol * fmax(fabs(y[i]), fabs(yn[i]));
            double ei = dopri_error(h, k, i) / sc;
            err += ei * ei;
        }
        err = sqrt(err / n);
        if (!isfinite(err)) return -1;
        if (scipy ? !(err < 1.0) : err > 1.0) {
            double fac = 0.9 * pow(err, -0.2);
            h *= fac < 0.2 ? 0.2 : fac;
            rejected = 1;
            continue;
        }
        if (scipy)
            for (int i = 0; i < n; i++)
                for (int j = 0; j < 4; j++)
                    q[4 * i + j] = f0[i] * DP_P[0][j] + k2[i] * DP_P[1][j] + k3[i] * DP_P[2][j] + k4[i] * DP_P[3][j]
                                   + k5[i] * DP_P[4][j] + k6[i] * DP_P[5][j] + k7[i] * DP_P[6][j];
        /* terminal events between t and t1, located on the step's interpolant */
        int fell = dopri_event(o, yn);
        double t_stop = t1;
        if (fell) {
            double lo = t, hi = t1;
            for (int it = 0; it < 200; it++) {
                double mid = 0.5 * (lo + hi);
                if (!scipy && it == 60) break;
                if (mid <= lo || mid >= hi) break;
                if (scipy) dopri_quartic(n, t, h, y, q, mid, yi);
                else dopri_hermite(n, t, t1, y, yn, f0, k7, mid, yi);
                if (dopri_event(o, yi)) hi = mid; else lo = mid;
            }
            t_stop = hi;
        }
        while (next < n_t && t_out[next] <= t_stop) {
            if (scipy) dopri_quartic(n, t, h, y, q, t_out[next], yi);
            else dopri_hermite(n, t, t1, y, yn, f0, k7, t_out[next], yi);
            for (int i = 0; i < n; i++) out[i * n_t + next] = yi[i];
            next++;
        }
        if (fell) { *t_end = t_stop; return 1; }
        t = t1;
        for (int i = 0; i < n; i++) { y[i] = yn[i]; f0[i] = k7[i]; }
        double fac = err == 0 ? 10.0 : 0.9 * pow(err, -0.2);
        if (fac > 10.0) fac = 10.0;
        if (scipy && rejected && fac > 1.0) fac = 1.0;
        h *= fac;
        rejected = 0;
        if (++steps > o->max_steps) return -3;
    }
    *t_end = tf;
    return 0;
}

#endif
