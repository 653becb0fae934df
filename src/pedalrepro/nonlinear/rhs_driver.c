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
   Whole runs in C: adaptive Dormand-Prince 5(4) (the scheme of scipy's RK45 and MATLAB's
   ode45) with the same error norm as scipy (rms of err / (atol + rtol max(|y|, |y_new|))),
   output on a fixed grid by cubic Hermite interpolation between steps, and a terminal event
   |roll| = fall located by bisection on the interpolant. Forcing: harmonic roll/steer torques
   (Eq 3.14) and/or prescribed leg motion given as Fourier series.                       */

typedef struct {
    int n_harm; const double *harm_w; const double *roll_re; const double *roll_im;
    const double *steer_re; const double *steer_im;          /* torque coefficients * w^2 */
    int n_spec; int n_four; double omega; const double *four_re; const double *four_im;
    const double *slope;                                       /* spec: n_spec/3 signals */
    const double *p;
    double steer_limit;           /* |steer| at which the run ends like a fall (arm reach) */
} forcing_t;

static int eval_f(const forcing_t *fc, double t, const double *x, double *dx) {
    double tr = 0.0, ts = 0.0, s[64 * 3];
    for (int k = 0; k < fc->n_harm; k++) {
        double c = cos(fc->harm_w[k] * t), sn = sin(fc->harm_w[k] * t);
        tr += fc->roll_re[k] * c - fc->roll_im[k] * sn;
        ts += fc->steer_re[k] * c - fc->steer_im[k] * sn;
    }
    int m = fc->n_spec / 3;
    if (m > 0) {
        for (int i = 0; i < m; i++) { s[i] = fc->slope[i] * t; s[m + i] = fc->slope[i]; s[2 * m + i] = 0.0; }
        double c1 = cos(fc->omega * t), s1 = sin(fc->omega * t), c = 1.0, sn = 0.0;
        for (int n = 0; n < fc->n_four; n++) {
            double wn = n * fc->omega;
            if (n > 0) { double cn = c * c1 - sn * s1; sn = sn * c1 + c * s1; c = cn; }
            for (int i = 0; i < m; i++) {
                double re = fc->four_re[i * fc->n_four + n], im = fc->four_im[i * fc->n_four + n];
                double val = re * c - im * sn;              /* Re(coef e^{i wn t}) */
                s[i] += val;
                s[m + i] += -wn * (re * sn + im * c);       /* Re(i wn coef e^{...}) */
                s[2 * m + i] += -wn * wn * val;
            }
        }
    }
    return full_rhs(x, fc->p, s, tr, ts, dx, 0);
}

static void hermite(double t0, double t1, const double *y0, const double *y1, const double *f0,
                    const double *f1, double t, double *out) {
    double h = t1 - t0, s = (t - t0) / h, s2 = s * s, s3 = s2 * s;
    double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (int i = 0; i < 6; i++) out[i] = h00 * y0[i] + h10 * h * f0[i] + h01 * y1[i] + h11 * h * f1[i];
}

/* Returns 0 finished, 1 fell, negative on failure. out: 6 x n_t (row per state, NaN after a fall). */
int integrate(const forcing_t *fc, const double *x0, const double *t_out, int n_t, double rtol,
              double atol, double fall, double *out, double *t_end, long *n_rhs) {
    static const double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
    static const double a21 = 1.0 / 5;
    static const double a31 = 3.0 / 40, a32 = 9.0 / 40;
    static const double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
    static const double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
    static const double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176, a65 = -5103.0 / 18656;
    static const double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
    static const double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525, e7 = -1.0 / 40;
    double y[6], f0[6], k2[6], k3[6], k4[6], k5[6], k6[6], k7[6], yn[6], tmp[6], yi[6];
    double t = t_out[0], tf = t_out[n_t - 1];
    for (int i = 0; i < 6; i++) y[i] = x0[i];
    for (int j = 0; j < n_t * 6; j++) out[j] = NAN;
    *n_rhs = 0;
    if (eval_f(fc, t, y, f0)) return -1;
    (*n_rhs)++;
    for (int i = 0; i < 6; i++) out[i * n_t] = y[i];
    int next = 1;
    /* initial step as in Hairer's / scipy's select_initial_step (simplified) */
    double d0 = 0, d1 = 0;
    for (int i = 0; i < 6; i++) { double sc = atol + rtol * fabs(y[i]); d0 += (y[i] / sc) * (y[i] / sc); d1 += (f0[i] / sc) * (f0[i] / sc); }
    d0 = sqrt(d0 / 6); d1 = sqrt(d1 / 6);
    double h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h > tf - t) h = tf - t;
    int steps = 0;
    while (t < tf) {
        if (h < 1e-12) return -2;
        if (t + h > tf) h = tf - t;
        for (int i = 0; i < 6; i++) tmp[i] = y[i] + h * a21 * f0[i];
        if (eval_f(fc, t + c2 * h, tmp, k2)) return -1;
        for (int i = 0; i < 6; i++) tmp[i] = y[i] + h * (a31 * f0[i] + a32 * k2[i]);
        if (eval_f(fc, t + c3 * h, tmp, k3)) return -1;
        for (int i = 0; i < 6; i++) tmp[i] = y[i] + h * (a41 * f0[i] + a42 * k2[i] + a43 * k3[i]);
        if (eval_f(fc, t + c4 * h, tmp, k4)) return -1;
        for (int i = 0; i < 6; i++) tmp[i] = y[i] + h * (a51 * f0[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
        if (eval_f(fc, t + c5 * h, tmp, k5)) return -1;
        for (int i = 0; i < 6; i++) tmp[i] = y[i] + h * (a61 * f0[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
        if (eval_f(fc, t + h, tmp, k6)) return -1;
        for (int i = 0; i < 6; i++) yn[i] = y[i] + h * (b1 * f0[i] + b3 * k3[i] + b4 * k4[i] + b5 * k5[i] + b6 * k6[i]);
        if (eval_f(fc, t + h, yn, k7)) return -1;
        *n_rhs += 6;
        double err = 0;
        for (int i = 0; i < 6; i++) {
            double sc = atol + rtol * fmax(fabs(y[i]), fabs(yn[i]));
            double ei = h * (e1 * f0[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]) / sc;
            err += ei * ei;
        }
        err = sqrt(err / 6);
        if (!isfinite(err)) return -1;
        if (err > 1.0) {
            double fac = 0.9 * pow(err, -0.2);
            h *= fac < 0.2 ? 0.2 : fac;
            continue;
        }
        double t1 = t + h;
        /* fall event between t and t1 (or the arms' reach: |steer| = steer_limit) */
        int fell = fabs(yn[0]) >= fall || fabs(yn[2]) >= fc->steer_limit;
        double t_stop = t1;
        if (fell) {
            double lo = t, hi = t1;
            for (int it = 0; it < 60; it++) {
                double mid = 0.5 * (lo + hi);
                hermite(t, t1, y, yn, f0, k7, mid, yi);
                if (fabs(yi[0]) >= fall || fabs(yi[2]) >= fc->steer_limit) hi = mid; else lo = mid;
            }
            t_stop = hi;
        }
        while (next < n_t && t_out[next] <= t_stop) {
            hermite(t, t1, y, yn, f0, k7, t_out[next], yi);
            for (int i = 0; i < 6; i++) out[i * n_t + next] = yi[i];
            next++;
        }
        if (fell) { *t_end = t_stop; return 1; }
        t = t1;
        for (int i = 0; i < 6; i++) { y[i] = yn[i]; f0[i] = k7[i]; }
        double fac = err == 0 ? 10.0 : 0.9 * pow(err, -0.2);
        h *= fac > 10.0 ? 10.0 : fac;
        if (++steps > 50000000) return -3;
    }
    *t_end = tf;
    return 0;
}
