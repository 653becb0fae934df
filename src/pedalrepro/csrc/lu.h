/* The one LU factorisation of the compiled code (pedalrepro/csrc): partial pivoting, row-major,
   in place. Used by the model's right-hand side (model_rhs.h) for the dependent speeds, the
   constraint accelerations and the reduced Kane equations. */
#ifndef PEDALREPRO_LU_H
#define PEDALREPRO_LU_H

#include <math.h>

/* Most right-hand sides of one lu_solve_columns call. */
#define LU_MAX_COLUMNS 8

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

static void lu_solve_columns(int n, int m, const double *restrict lu, const int *restrict piv,
                             double *restrict b) {
    /* Solve (P L U) X = B in place for the m columns of B (row-major n x m, column c at
       b[i * m + c]) with the factors of lu_factor: every row swap first (the factor swapped
       whole rows, multipliers included), then L and U. Each column gets exactly the operations
       of a single solve in the same order (bit-identical to solving them one by one); the
       columns go in lockstep so that their chains of dependent divisions overlap (the three
       columns of C = -A_dep^-1 A_ind: 0.45 -> 0.35 us per model_speeds call on this machine). */
    for (int k = 0; k < n; k++)
        if (piv[k] != k)
            for (int c = 0; c < m; c++) { double tmp = b[k * m + c]; b[k * m + c] = b[piv[k] * m + c]; b[piv[k] * m + c] = tmp; }
    for (int k = 0; k < n; k++)
        for (int i = k + 1; i < n; i++) {
            const double l = lu[i * n + k];
            for (int c = 0; c < m; c++) b[i * m + c] -= l * b[k * m + c];
        }
    for (int i = n - 1; i >= 0; i--) {
        double acc[LU_MAX_COLUMNS];
        for (int c = 0; c < m; c++) acc[c] = b[i * m + c];
        for (int j = i + 1; j < n; j++) {
            const double l = lu[i * n + j];
            for (int c = 0; c < m; c++) acc[c] -= l * b[j * m + c];
        }
        for (int c = 0; c < m; c++) b[i * m + c] = acc[c] / lu[i * n + i];
    }
}

static void lu_solve(int n, const double *restrict lu, const int *restrict piv, double *restrict b) {
    /* Solve (P L U) x = b in place for one right-hand side. */
    lu_solve_columns(n, 1, lu, piv, b);
}

#endif
