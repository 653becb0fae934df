/* Hand-written part of the compiled right-hand side (pedalrepro.nonlinear.codegen):
   dependent speeds from A u = 0, then Kane's equations reduced to the three independent speeds
   (the null-space form of the Lagrange-multiplier system [M A^T; A 0] [u'; lam] = [F; -b]:
   with u_dep = C u_ind, C = -A_dep^-1 A_ind, the accelerations u' = B u'_ind + e, B = [I; C],
   e = [0; -A_dep^-1 b], satisfy (B^T M B) u'_ind = B^T (F - M e), since A B = 0). One LU
   factorisation of A_dep serves the speeds and the accelerations; the reduced system is 3 x 3
   instead of 13 x 13. The Python reference (NonlinearModel.accelerations) solves the 13 x 13
   system: the two agree to rounding (tests/test_nonlinear.py). */

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

static const int U_IND[3] = {3, 5, 6};
static const int U_DEP[5] = {0, 1, 2, 4, 7};

/* x = [roll, pitch, steer, u_roll, u_rear, u_steer]; returns 0 on success. */
int full_rhs(const double *x, const double *p, const double *s, double t_roll, double t_steer,
             double *dx, double *u_out) {
    double q[8] = {0}, u[8] = {0}, A[40], M[64], F[8], b[5];
    q[3] = x[0]; q[4] = x[1]; q[6] = x[2];
    u[3] = x[3]; u[5] = x[4]; u[6] = x[5];
    constraint_matrix(q, p, A);
    double Ad[25], C[15], col[5];
    int piv[5];
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) Ad[i * 5 + j] = A[i * 8 + U_DEP[j]];
    if (lu_factor(5, Ad, piv)) return 1;
    for (int k = 0; k < 3; k++) {                       /* C = -A_dep^-1 A_ind */
        for (int i = 0; i < 5; i++) col[i] = -A[i * 8 + U_IND[k]];
        lu_solve(5, Ad, piv, col);
        for (int i = 0; i < 5; i++) C[i * 3 + k] = col[i];
    }
    for (int j = 0; j < 5; j++) {
        double acc = 0.0;
        for (int k = 0; k < 3; k++) acc += C[j * 3 + k] * u[U_IND[k]];
        u[U_DEP[j]] = acc;
    }
    dynamics(q, u, p, s, M, F, b);
    F[3] += t_roll; F[6] += t_steer;
    double B[24] = {0}, e[8] = {0}, d[5];
    for (int i = 0; i < 5; i++) d[i] = -b[i];
    lu_solve(5, Ad, piv, d);                            /* u'_dep = C u'_ind + d */
    for (int k = 0; k < 3; k++) B[U_IND[k] * 3 + k] = 1.0;
    for (int j = 0; j < 5; j++) {
        for (int k = 0; k < 3; k++) B[U_DEP[j] * 3 + k] = C[j * 3 + k];
        e[U_DEP[j]] = d[j];
    }
    double MB[24], g[8], R[9], r[3];
    for (int i = 0; i < 8; i++) {
        double m0 = 0.0, m1 = 0.0, m2 = 0.0, me = 0.0;
        for (int j = 0; j < 8; j++) {
            double mij = M[i * 8 + j];
            m0 += mij * B[j * 3]; m1 += mij * B[j * 3 + 1]; m2 += mij * B[j * 3 + 2];
            me += mij * e[j];
        }
        MB[i * 3] = m0; MB[i * 3 + 1] = m1; MB[i * 3 + 2] = m2;
        g[i] = F[i] - me;
    }
    for (int k = 0; k < 3; k++) {
        for (int l = 0; l < 3; l++) {
            double acc = 0.0;
            for (int i = 0; i < 8; i++) acc += B[i * 3 + k] * MB[i * 3 + l];
            R[k * 3 + l] = acc;
        }
        double acc = 0.0;
        for (int i = 0; i < 8; i++) acc += B[i * 3 + k] * g[i];
        r[k] = acc;
    }
    int piv3[3];
    if (lu_factor(3, R, piv3)) return 2;
    lu_solve(3, R, piv3, r);
    dx[0] = u[3]; dx[1] = u[4]; dx[2] = u[6];
    dx[3] = r[0]; dx[4] = r[1]; dx[5] = r[2];
    if (u_out) for (int i = 0; i < 8; i++) u_out[i] = u[i];
    for (int i = 0; i < 6; i++) if (!isfinite(dx[i])) return 3;
    return 0;
}

/* ------------------------------------------------------------------------------------------
   The forced right-hand side for the integrator (pedalrepro/integrator/dopri.c, compiled into
   the same library): harmonic roll/steer torques (Eq 3.14) and/or prescribed leg motion given
   as Fourier series. Python side: pedalrepro.nonlinear.simulate.ForcedModel.               */

/* forcing_t and pedal_forcing: forcing.c, prepended to this file. */

int forced_rhs(const void *ctx, double t, const double *x, double *dx) {
    const forcing_t *fc = (const forcing_t *)ctx;
    double tr, ts, s[64 * 3];
    pedal_forcing(fc, t, s, &tr, &ts);
    return full_rhs(x, fc->p, s, tr, ts, dx, 0);
}
