/* pedalrepro.integrator: whole runs in C with an adaptive Dormand-Prince 5(4) pair (the scheme
   of scipy's RK45 and MATLAB's ode45) and terminal fall events |x[i]| >= limit.

   The right-hand side is a function pointer with a context (a model's parameters and forcing),
   so one integrator serves the non-linear models (pedalrepro/nonlinear/rhs_driver.c) and the
   linear models (linear_rhs.c). Two variants (dopri_options.variant):

   DOPRI_SCIPY   scipy.integrate.solve_ivp(method="RK45") step for step: its initial step
                 (Hairer's algorithm, select_initial_step), its step-size rules (safety 0.9,
                 factors 0.2..10, no growth right after a rejection, accept when err < 1), its
                 quartic dense output for the samples and the events (located on that
                 interpolant to round-off, as scipy's brentq at 4 eps).
   DOPRI_HERMITE the project's first compiled scheme, kept for the NT/NP sweeps so that their
                 tables stay byte-identical: a simplified initial step, cubic Hermite samples
                 between steps and events bisected on that interpolant.

   Both use the error norm of scipy: rms of err / (atol + rtol max(|y|, |y_new|)).       */

#include <math.h>

#define DOPRI_NMAX 32
#define DOPRI_SCIPY 0
#define DOPRI_HERMITE 1

typedef int (*dopri_rhs)(const void *ctx, double t, const double *x, double *dx);

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

static double dopri_rms(int n, const double *v) {
    double s = 0.0;
    for (int i = 0; i < n; i++) s += v[i] * v[i];
    return sqrt(s / n);
}

/* Returns 0 finished, 1 an event ended the run, negative on failure (-1 non-finite state or the
   right-hand side failed, -2 step size underflow, -3 too many steps, -4 bad arguments).
   out: n x n_t (row per state, NaN after an event). The run starts at t_out[0] from x0. */
int dopri_integrate(dopri_rhs f, const void *ctx, int n, const double *x0, const double *t_out,
                    int n_t, const dopri_options *o, double *out, double *t_end, long *n_rhs) {
    static const double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
    static const double a21 = 1.0 / 5;
    static const double a31 = 3.0 / 40, a32 = 9.0 / 40;
    static const double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
    static const double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
    static const double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176, a65 = -5103.0 / 18656;
    static const double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
    static const double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525, e7 = -1.0 / 40;
    /* scipy's RK45.P (dense output), rows = stages */
    static const double P[7][4] = {
        {1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0, -12715105075.0 / 11282082432.0},
        {0.0, 0.0, 0.0, 0.0},
        {0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0, 87487479700.0 / 32700410799.0},
        {0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0, -10690763975.0 / 1880347072.0},
        {0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0, 701980252875.0 / 199316789632.0},
        {0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0, -1453857185.0 / 822651844.0},
        {0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0}};
    double y[DOPRI_NMAX], f0[DOPRI_NMAX], k2[DOPRI_NMAX], k3[DOPRI_NMAX], k4[DOPRI_NMAX];
    double k5[DOPRI_NMAX], k6[DOPRI_NMAX], k7[DOPRI_NMAX], yn[DOPRI_NMAX], tmp[DOPRI_NMAX];
    double yi[DOPRI_NMAX], q[4 * DOPRI_NMAX];
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
        for (int i = 0; i < n; i++) tmp[i] = y[i] + h * a21 * f0[i];
        if (f(ctx, t + c2 * h, tmp, k2)) return -1;
        for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (a31 * f0[i] + a32 * k2[i]);
        if (f(ctx, t + c3 * h, tmp, k3)) return -1;
        for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (a41 * f0[i] + a42 * k2[i] + a43 * k3[i]);
        if (f(ctx, t + c4 * h, tmp, k4)) return -1;
        for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (a51 * f0[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
        if (f(ctx, t + c5 * h, tmp, k5)) return -1;
        for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (a61 * f0[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
        if (f(ctx, t + h, tmp, k6)) return -1;
        for (int i = 0; i < n; i++) yn[i] = y[i] + h * (b1 * f0[i] + b3 * k3[i] + b4 * k4[i] + b5 * k5[i] + b6 * k6[i]);
        if (f(ctx, t + h, yn, k7)) return -1;
        *n_rhs += 6;
        double err = 0;
        for (int i = 0; i < n; i++) {
            double sc = atol + rtol * fmax(fabs(y[i]), fabs(yn[i]));
            double ei = h * (e1 * f0[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]) / sc;
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
                    q[4 * i + j] = f0[i] * P[0][j] + k2[i] * P[1][j] + k3[i] * P[2][j] + k4[i] * P[3][j]
                                   + k5[i] * P[4][j] + k6[i] * P[5][j] + k7[i] * P[6][j];
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
