/* The one LU factorisation of the compiled code (pedalrepro/csrc): partial pivoting, row-major,
   in place. Used by the model's right-hand side (model_rhs.h) for the dependent speeds, the
   constraint accelerations and the reduced Kane equations. */
#ifndef PEDALREPRO_LU_H
#define PEDALREPRO_LU_H

#include <math.h>

static int lu_factor(int n, double *restrict a, int *restrict piv) {
    /* a = P L U with partial pivoting, in place (row-major n x n; L unit lower, below the
       diagonal); piv[k]: the row swapped with row k. Returns 1 for a singular matrix. */
    for (int k = 0; k < n; k++) {
        int pk = k; double best = fabs(a[k * n + k]);
        for (int i = k + 1; i < n; i++) { double v = fabs(a[i * n + k]); if (v > best) { best = v; pk = i; } }
        if (best == 0.0) return 1;
        piv[k] = pk;
        if (pk != k)
            for (int j = 0; j < n; j++) { double tmp = a[k * n + j]; a[k * n + j] = a[pk * n + j]; a[pk * n + j] = tmp; }
        for (int i = k + 1; i < n; i++) {
            double f = a[i * n + k] / a[k * n + k];
            a[i * n + k] = f;
            for (int j = k + 1; j < n; j++) a[i * n + j] -= f * a[k * n + j];
        }
    }
    return 0;
}

static void lu_solve(int n, const double *restrict lu, const int *restrict piv, double *restrict b) {
    /* Solve (P L U) x = b in place with the factors of lu_factor: every row swap first (the
       factor swapped whole rows, multipliers included), then L and U. */
    for (int k = 0; k < n; k++)
        if (piv[k] != k) { double tmp = b[k]; b[k] = b[piv[k]]; b[piv[k]] = tmp; }
    for (int k = 0; k < n; k++)
        for (int i = k + 1; i < n; i++) b[i] -= lu[i * n + k] * b[k];
    for (int i = n - 1; i >= 0; i--) {
        double acc = b[i];
        for (int j = i + 1; j < n; j++) acc -= lu[i * n + j] * b[j];
        b[i] = acc / lu[i * n + i];
    }
}

#endif
