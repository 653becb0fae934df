/* Right-hand side of a linear time-invariant system with harmonic forcing (pedalrepro.integrator):

       x' = A x + e_rows Re( sum_k amp[k] exp(i w_k t) )

   A (n x n, row-major); the forcing enters the states rows[0..m-1] (for the linear bicycle
   models, Eq 3.1 in first-order form, the two accelerations: M^-1 times the pedalling torques of
   Eq 3.14). amp_re/amp_im are (n_harm x m), row-major.                                  */
#ifndef PEDALREPRO_LINEAR_RHS_H
#define PEDALREPRO_LINEAR_RHS_H

#include <math.h>

typedef struct {
    int n;
    const double *a;
    int n_harm; const double *w; const double *amp_re; const double *amp_im;
    int m; const int *rows;
} linear_system;

int linear_rhs(const void *ctx, double t, const double *x, double *dx) {
    const linear_system *s = (const linear_system *)ctx;
    for (int i = 0; i < s->n; i++) {
        double acc = 0.0;
        for (int j = 0; j < s->n; j++) acc += s->a[i * s->n + j] * x[j];
        dx[i] = acc;
    }
    for (int k = 0; k < s->n_harm; k++) {
        double c = cos(s->w[k] * t), sn = sin(s->w[k] * t);
        for (int j = 0; j < s->m; j++)
            dx[s->rows[j]] += s->amp_re[k * s->m + j] * c - s->amp_im[k * s->m + j] * sn;
    }
    for (int i = 0; i < s->n; i++) if (!isfinite(dx[i])) return 1;
    return 0;
}

#endif
