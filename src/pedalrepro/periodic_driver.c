/* Periodic-orbit driver (pedalrepro.periodic), appended to a model's generated C code.

   Uses only the two generated functions constraint_matrix(q, p, A) and
   dynamics(q, u, p, s, M, F, b) (pedalrepro.nonlinear.codegen). Everything else is here, with a
   po_ prefix so that it never clashes with the model's own driver.

   Reduced state y = [roll, pitch, steer, roll rate, steer rate]; the rear-wheel rate is held at
   u_rear by a generalised force tau on the rear-wheel rotation (a hub torque) chosen at every
   instant so that the rear-wheel acceleration is zero (the constant forward speed that the
   linearised model assumes). Forcing: harmonic roll/steer torques (Eq 3.14) and/or prescribed
   leg motion given as Fourier series (as the model's own driver). The flow integrates y with an
   adaptive Dormand-Prince 5(4) pair, optionally together with nvar variational columns
   (directional derivatives of the right-hand side by central or forward differences) and five quadratures:
   roll cos(w t), roll sin(w t), steer cos(w t), steer sin(w t) and tau. */

#include <math.h>
#include <string.h>

typedef struct {
    forcing_t f;          /* the pedalling forcing and the parameters (forcing.c, prepended) */
    double u_rear;        /* held rear-wheel rate */
    double omega_q;       /* frequency of the Fourier quadratures (the cadence) */
    int iq[3];            /* indices of roll, pitch, steer in q */
    int iu[3];            /* indices of the independent speeds: roll, rear wheel, steer */
    int idep[5];          /* indices of the dependent speeds */
    double fd_step;       /* relative step of the directional differences */
    int central;          /* 1: central differences (2 evaluations per column), 0: forward */
} po_forcing;

static int po_solve(int n, int nrhs, double *a, double *b) {
    /* Gaussian elimination with partial pivoting; a n x n, b n x nrhs, row-major, overwritten. */
    for (int k = 0; k < n; k++) {
        int piv = k; double best = fabs(a[k * n + k]);
        for (int i = k + 1; i < n; i++) { double v = fabs(a[i * n + k]); if (v > best) { best = v; piv = i; } }
        if (best == 0.0) return 1;
        if (piv != k) {
            for (int j = 0; j < n; j++) { double t = a[k * n + j]; a[k * n + j] = a[piv * n + j]; a[piv * n + j] = t; }
            for (int j = 0; j < nrhs; j++) { double t = b[k * nrhs + j]; b[k * nrhs + j] = b[piv * nrhs + j]; b[piv * nrhs + j] = t; }
        }
        for (int i = k + 1; i < n; i++) {
            double f = a[i * n + k] / a[k * n + k];
            if (f == 0.0) continue;
            for (int j = k; j < n; j++) a[i * n + j] -= f * a[k * n + j];
            for (int j = 0; j < nrhs; j++) b[i * nrhs + j] -= f * b[k * nrhs + j];
        }
    }
    for (int i = n - 1; i >= 0; i--) {
        for (int j = 0; j < nrhs; j++) {
            double acc = b[i * nrhs + j];
            for (int l = i + 1; l < n; l++) acc -= a[i * n + l] * b[l * nrhs + j];
            b[i * nrhs + j] = acc / a[i * n + i];
        }
    }
    return 0;
}

/* Dependent speeds from A(q) u = 0 (independent speeds already in u); A returned. */
static int po_speeds(const po_forcing *fc, const double *q, double *u, double *A) {
    constraint_matrix(q, fc->f.p, A);
    double Ad[25], r[5];
    for (int i = 0; i < 5; i++) {
        r[i] = 0.0;
        for (int k = 0; k < 3; k++) r[i] -= A[i * 8 + fc->iu[k]] * u[fc->iu[k]];
        for (int j = 0; j < 5; j++) Ad[i * 5 + j] = A[i * 8 + fc->idep[j]];
    }
    if (po_solve(5, 1, Ad, r)) return 1;
    for (int j = 0; j < 5; j++) u[fc->idep[j]] = r[j];
    return 0;
}

/* Reduced right-hand side with the held rear-wheel rate, forcing given; tau: the holding
   generalised force. */
static int po_rhs_f(const po_forcing *fc, const double *s, double tr, double ts, const double *y,
                    double *dy, double *tau) {
    double q[8] = {0}, u[8] = {0}, A[40], M[64], F[8], b[5];
    const int ir = fc->iq[0], ip = fc->iq[1], is = fc->iq[2];
    const int ur = fc->iu[0], uw = fc->iu[1], us = fc->iu[2];
    q[ir] = y[0]; q[ip] = y[1]; q[is] = y[2];
    u[ur] = y[3]; u[uw] = fc->u_rear; u[us] = y[4];
    if (po_speeds(fc, q, u, A)) return 1;
    dynamics(q, u, fc->f.p, s, M, F, b);
    F[ur] += tr; F[us] += ts;
    double K[169], r[26];
    memset(K, 0, sizeof K);
    for (int i = 0; i < 8; i++) {
        for (int j = 0; j < 8; j++) K[i * 13 + j] = M[i * 8 + j];
        for (int j = 0; j < 5; j++) { K[i * 13 + 8 + j] = A[j * 8 + i]; K[(8 + j) * 13 + i] = A[j * 8 + i]; }
        r[2 * i] = F[i]; r[2 * i + 1] = (i == uw) ? 1.0 : 0.0;
    }
    for (int j = 0; j < 5; j++) { r[2 * (8 + j)] = -b[j]; r[2 * (8 + j) + 1] = 0.0; }
    if (po_solve(13, 2, K, r)) return 2;
    double g = -r[2 * uw] / r[2 * uw + 1];
    dy[0] = u[ur]; dy[1] = u[ip]; dy[2] = u[us];
    dy[3] = r[2 * ur] + g * r[2 * ur + 1];
    dy[4] = r[2 * us] + g * r[2 * us + 1];
    if (tau) *tau = g;
    for (int i = 0; i < 5; i++) if (!isfinite(dy[i])) return 3;
    return 0;
}

/* Reduced right-hand side at time t (exported for tests and the symmetry check). */
int po_rhs(const po_forcing *fc, double t, const double *y, double *dy, double *tau) {
    double s[64 * 3], tr, ts;
    pedal_forcing(&fc->f, t, s, &tr, &ts);
    return po_rhs_f(fc, s, tr, ts, y, dy, tau);
}

/* Pitch on the ground-contact manifold at (roll, steer), integrating the pitch rate of the
   velocity constraints along the straight path from upright (pitch0) with classical RK4, and
   its derivatives with respect to roll and steer at the end point. */
int po_pitch(const po_forcing *fc, double roll, double steer, double pitch0, int steps,
             double *pitch, double *dpitch) {
    double q[8] = {0}, u[8] = {0}, A[40];
    const int ir = fc->iq[0], ip = fc->iq[1], is = fc->iq[2];
    double p = pitch0, h = 1.0 / steps, k[4];
    for (int n = 0; n < steps; n++) {
        double s0 = n * h;
        double ss[4] = {s0, s0 + 0.5 * h, s0 + 0.5 * h, s0 + h};
        for (int st = 0; st < 4; st++) {
            double pp = p + (st == 0 ? 0.0 : (st == 3 ? h : 0.5 * h) * k[st - 1]);
            memset(q, 0, sizeof q); memset(u, 0, sizeof u);
            q[ir] = ss[st] * roll; q[ip] = pp; q[is] = ss[st] * steer;
            u[fc->iu[0]] = roll; u[fc->iu[2]] = steer;
            if (po_speeds(fc, q, u, A)) return 1;
            k[st] = u[ip];
        }
        p += h / 6.0 * (k[0] + 2 * k[1] + 2 * k[2] + k[3]);
    }
    *pitch = p;
    for (int j = 0; j < 2; j++) {
        memset(q, 0, sizeof q); memset(u, 0, sizeof u);
        q[ir] = roll; q[ip] = p; q[is] = steer;
        u[fc->iu[j == 0 ? 0 : 2]] = 1.0;
        if (po_speeds(fc, q, u, A)) return 1;
        dpitch[j] = u[ip];
    }
    return 0;
}

/* Augmented right-hand side: state (5), nvar variational columns (5 each), quadratures (5). */
static int po_aug(const po_forcing *fc, double t, const double *Y, int nvar, double *dY) {
    double tau, yp[5], ym[5], fp[5], fm[5], s[64 * 3], tr, ts;
    pedal_forcing(&fc->f, t, s, &tr, &ts);
    if (po_rhs_f(fc, s, tr, ts, Y, dY, &tau)) return 1;
    double ny = 0.0;
    for (int i = 0; i < 5; i++) ny += Y[i] * Y[i];
    ny = sqrt(ny);
    for (int j = 0; j < nvar; j++) {
        const double *v = Y + 5 + 5 * j;
        double nv = 0.0;
        for (int i = 0; i < 5; i++) nv += v[i] * v[i];
        nv = sqrt(nv);
        double *out = dY + 5 + 5 * j;
        if (nv == 0.0) { for (int i = 0; i < 5; i++) out[i] = 0.0; continue; }
        double e = fc->fd_step * (1.0 + ny) / nv;
        for (int i = 0; i < 5; i++) { yp[i] = Y[i] + e * v[i]; ym[i] = Y[i] - e * v[i]; }
        if (fc->central) {
            if (po_rhs_f(fc, s, tr, ts, yp, fp, 0) || po_rhs_f(fc, s, tr, ts, ym, fm, 0)) return 1;
            for (int i = 0; i < 5; i++) out[i] = (fp[i] - fm[i]) / (2.0 * e);
        } else {
            if (po_rhs_f(fc, s, tr, ts, yp, fp, 0)) return 1;
            for (int i = 0; i < 5; i++) out[i] = (fp[i] - dY[i]) / e;
        }
    }
    double *qd = dY + 5 + 5 * nvar, c = cos(fc->omega_q * t), sn = sin(fc->omega_q * t);
    qd[0] = Y[0] * c; qd[1] = Y[0] * sn; qd[2] = Y[2] * c; qd[3] = Y[2] * sn; qd[4] = tau;
    return 0;
}

#define PO_MAXN (5 + 5 * 8 + 5)

/* Flow from t0 to t1. Y0/Y1: augmented vectors (5 + 5 nvar + 5, quadratures start at Y0's).
   Error control on the five states only (rms of err / (atol_i + rtol max(|y|, |y_new|))).
   h_io: initial step (<= 0: automatic), returns the last accepted step. peak: max |roll|,
   max |steer| at the steps. Returns 0, or -1 non-finite/singular, -2 step underflow,
   -3 too many steps, -4 too many variational columns. */
int po_flow(const po_forcing *fc, double t0, double t1, const double *Y0, int nvar,
            double rtol, const double *atol, double *Y1, double *peak, long *n_rhs,
            double *h_io) {
    static const double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
    static const double a21 = 1.0 / 5;
    static const double a31 = 3.0 / 40, a32 = 9.0 / 40;
    static const double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
    static const double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
    static const double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176, a65 = -5103.0 / 18656;
    static const double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
    static const double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525, e7 = -1.0 / 40;
    if (nvar > 8) return -4;
    const int N = 5 + 5 * nvar + 5;
    const int per = 1 + (fc->central ? 2 : 1) * nvar;
    double y[PO_MAXN], f0[PO_MAXN], k2[PO_MAXN], k3[PO_MAXN], k4[PO_MAXN], k5[PO_MAXN],
        k6[PO_MAXN], k7[PO_MAXN], yn[PO_MAXN], tmp[PO_MAXN];
    double t = t0;
    memcpy(y, Y0, N * sizeof(double));
    peak[0] = fabs(y[0]); peak[1] = fabs(y[2]);
    *n_rhs = 0;
    if (po_aug(fc, t, y, nvar, f0)) return -1;
    *n_rhs += per;
    double h = *h_io;
    if (!(h > 0)) {
        double d0 = 0, d1 = 0;
        for (int i = 0; i < 5; i++) { double sc = atol[i] + rtol * fabs(y[i]); d0 += (y[i] / sc) * (y[i] / sc); d1 += (f0[i] / sc) * (f0[i] / sc); }
        d0 = sqrt(d0 / 5); d1 = sqrt(d1 / 5);
        h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    }
    long steps = 0;
    while (t < t1) {
        if (h > t1 - t) h = t1 - t;
        if (h < 1e-14 * (1.0 + fabs(t))) return -2;
        for (int i = 0; i < N; i++) tmp[i] = y[i] + h * a21 * f0[i];
        if (po_aug(fc, t + c2 * h, tmp, nvar, k2)) return -1;
        for (int i = 0; i < N; i++) tmp[i] = y[i] + h * (a31 * f0[i] + a32 * k2[i]);
        if (po_aug(fc, t + c3 * h, tmp, nvar, k3)) return -1;
        for (int i = 0; i < N; i++) tmp[i] = y[i] + h * (a41 * f0[i] + a42 * k2[i] + a43 * k3[i]);
        if (po_aug(fc, t + c4 * h, tmp, nvar, k4)) return -1;
        for (int i = 0; i < N; i++) tmp[i] = y[i] + h * (a51 * f0[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
        if (po_aug(fc, t + c5 * h, tmp, nvar, k5)) return -1;
        for (int i = 0; i < N; i++) tmp[i] = y[i] + h * (a61 * f0[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
        if (po_aug(fc, t + h, tmp, nvar, k6)) return -1;
        for (int i = 0; i < N; i++) yn[i] = y[i] + h * (b1 * f0[i] + b3 * k3[i] + b4 * k4[i] + b5 * k5[i] + b6 * k6[i]);
        if (po_aug(fc, t + h, yn, nvar, k7)) return -1;
        *n_rhs += 6 * per;
        double err = 0;
        for (int i = 0; i < 5; i++) {
            double sc = atol[i] + rtol * fmax(fabs(y[i]), fabs(yn[i]));
            double ei = h * (e1 * f0[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]) / sc;
            err += ei * ei;
        }
        err = sqrt(err / 5);
        if (!isfinite(err)) return -1;
        if (err > 1.0) {
            double fac = 0.9 * pow(err, -0.2);
            h *= fac < 0.2 ? 0.2 : fac;
            continue;
        }
        t = (t1 - t - h <= 1e-15 * (1.0 + fabs(t1))) ? t1 : t + h;
        memcpy(y, yn, N * sizeof(double));
        memcpy(f0, k7, N * sizeof(double));
        if (fabs(y[0]) > peak[0]) peak[0] = fabs(y[0]);
        if (fabs(y[2]) > peak[1]) peak[1] = fabs(y[2]);
        double fac = err == 0 ? 10.0 : 0.9 * pow(err, -0.2);
        double hn = h * (fac > 10.0 ? 10.0 : fac);
        if (t < t1) h = hn; else *h_io = hn;
        if (++steps > 10000000) return -3;
    }
    memcpy(Y1, y, N * sizeof(double));
    return 0;
}
