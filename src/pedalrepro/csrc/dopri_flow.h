/* The flow loop of the periodic orbits (pedalrepro.periodic): the Dormand-Prince 5(4) step of
   dopri.h over an augmented state (the state, its variational columns and quadratures) with the
   error controlled on the first n_err components only. */
#ifndef PEDALREPRO_DOPRI_FLOW_H
#define PEDALREPRO_DOPRI_FLOW_H

#include <string.h>
#include "dopri.h"

/* Flow of the n-vector Y0 from t0 to t1 into Y1. Error norm: rms over i < n_err of
   err_i / (atol_i + rtol max(|y_i|, |y_new,i|)); accept when <= 1. h_io: initial step (<= 0:
   automatic), returns the last accepted step's successor. peak[k]: max |y[peak_index[k]]| at the
   steps (n_peak of them). n_calls: right-hand-side calls. Returns 0, or -1 non-finite or the
   right-hand side failed, -2 step underflow, -3 too many steps, -4 bad arguments. */
static int dopri_flow(dopri_rhs f, const void *ctx, int n, int n_err, double t0, double t1,
                      const double *Y0, double rtol, const double *atol, double *Y1,
                      int n_peak, const int *peak_index, double *peak, long *n_calls,
                      double *h_io) {
    double y[DOPRI_FLOW_NMAX], f0[DOPRI_FLOW_NMAX], k2[DOPRI_FLOW_NMAX], k3[DOPRI_FLOW_NMAX],
        k4[DOPRI_FLOW_NMAX], k5[DOPRI_FLOW_NMAX], k6[DOPRI_FLOW_NMAX], k7[DOPRI_FLOW_NMAX],
        yn[DOPRI_FLOW_NMAX], tmp[DOPRI_FLOW_NMAX];
    double *const k[7] = {f0, k2, k3, k4, k5, k6, k7};
    if (n < 1 || n > DOPRI_FLOW_NMAX || n_err < 1 || n_err > n) return -4;
    double t = t0;
    memcpy(y, Y0, n * sizeof(double));
    for (int j = 0; j < n_peak; j++) peak[j] = fabs(y[peak_index[j]]);
    *n_calls = 0;
    if (f(ctx, t, y, f0)) return -1;
    (*n_calls)++;
    double h = *h_io;
    if (!(h > 0)) {
        double d0 = 0, d1 = 0;
        for (int i = 0; i < n_err; i++) { double sc = atol[i] + rtol * fabs(y[i]); d0 += (y[i] / sc) * (y[i] / sc); d1 += (f0[i] / sc) * (f0[i] / sc); }
        d0 = sqrt(d0 / n_err); d1 = sqrt(d1 / n_err);
        h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    }
    long steps = 0;
    while (t < t1) {
        if (h > t1 - t) h = t1 - t;
        if (h < 1e-14 * (1.0 + fabs(t))) return -2;
        if (dopri_step(f, ctx, n, t, h, y, k, yn, tmp)) return -1;
        *n_calls += 6;
        double err = 0;
        for (int i = 0; i < n_err; i++) {
            double sc = atol[i] + rtol * fmax(fabs(y[i]), fabs(yn[i]));
            double ei = dopri_error(h, k, i) / sc;
            err += ei * ei;
        }
        err = sqrt(err / n_err);
        if (!isfinite(err)) return -1;
        if (err > 1.0) {
            double fac = 0.9 * pow(err, -0.2);
            h *= fac < 0.2 ? 0.2 : fac;
            continue;
        }
        t = (t1 - t - h <= 1e-15 * (1.0 + fabs(t1))) ? t1 : t + h;
        memcpy(y, yn, n * sizeof(double));
        memcpy(f0, k7, n * sizeof(double));
        for (int j = 0; j < n_peak; j++)
            if (fabs(y[peak_index[j]]) > peak[j]) peak[j] = fabs(y[peak_index[j]]);
        double fac = err == 0 ? 10.0 : 0.9 * pow(err, -0.2);
        double hn = h * (fac > 10.0 ? 10.0 : fac);
        if (t < t1) h = hn; else *h_io = hn;
        if (++steps > 10000000) return -3;
    }
    memcpy(Y1, y, n * sizeof(double));
    return 0;
}

#endif
