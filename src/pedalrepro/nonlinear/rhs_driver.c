/* Hand-written part of the compiled right-hand side (pedalrepro.nonlinear.codegen):
   dependent speeds from A u = 0, then Kane's equations with Lagrange multipliers. */

static int solve_dense(int n, double *a, double *b) {
    /* Gaussian elimination with partial pivoting, a (n x n row-major) and b overwritten. */
    for (int k = 0; k < n; k++) {
        int piv = k; double best = fabs(a[k * n + k]);
        for (int i = k + 1; i < n; i++) { double v = fabs(a[i * n + k]); if (v > best) { best = v; piv = i; } }
        if (best == 0.0) return 1;
        if (piv != k) {
            for (int j = 0; j < n; j++) { double tmp = a[k * n + j]; a[k * n + j] = a[piv * n + j]; a[piv * n + j] = tmp; }
            double tmp = b[k]; b[k] = b[piv]; b[piv] = tmp;
        }
        for (int i = k + 1; i < n; i++) {
            double f = a[i * n + k] / a[k * n + k];
            if (f == 0.0) continue;
            for (int j = k; j < n; j++) a[i * n + j] -= f * a[k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (int i = n - 1; i >= 0; i--) {
        double acc = b[i];
        for (int j = i + 1; j < n; j++) acc -= a[i * n + j] * b[j];
        b[i] = acc / a[i * n + i];
    }
    return 0;
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
    double Ad[25], rhs[5];
    for (int i = 0; i < 5; i++) {
        rhs[i] = 0.0;
        for (int k = 0; k < 3; k++) rhs[i] -= A[i * 8 + U_IND[k]] * u[U_IND[k]];
        for (int j = 0; j < 5; j++) Ad[i * 5 + j] = A[i * 8 + U_DEP[j]];
    }
    if (solve_dense(5, Ad, rhs)) return 1;
    for (int j = 0; j < 5; j++) u[U_DEP[j]] = rhs[j];
    dynamics(q, u, p, s, M, F, b);
    F[3] += t_roll; F[6] += t_steer;
    double K[169], r[13];
    for (int i = 0; i < 13; i++) for (int j = 0; j < 13; j++) K[i * 13 + j] = 0.0;
    for (int i = 0; i < 8; i++) {
        for (int j = 0; j < 8; j++) K[i * 13 + j] = M[i * 8 + j];
        for (int j = 0; j < 5; j++) { K[i * 13 + 8 + j] = A[j * 8 + i]; K[(8 + j) * 13 + i] = A[j * 8 + i]; }
        r[i] = F[i];
    }
    for (int j = 0; j < 5; j++) r[8 + j] = -b[j];
    if (solve_dense(13, K, r)) return 2;
    dx[0] = u[3]; dx[1] = u[4]; dx[2] = u[6];
    dx[3] = r[3]; dx[4] = r[5]; dx[5] = r[6];
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
