/* The periodic-orbit library of a non-linear model (pedalrepro.periodic): the model's generated
   code (MODEL_C, -D and -I), the forcing, the held-wheel-rate right-hand side of model_rhs.h and
   the Dormand-Prince flow loop (dopri_flow.h).

   Reduced state y = [roll, pitch, steer, roll rate, steer rate]; the rear-wheel rate is held at
   u_rear by a hub torque tau chosen at every instant so that the rear-wheel acceleration is zero
   (the constant forward speed that the linearised model assumes). The flow integrates y,
   optionally together with nvar variational columns (directional derivatives of the right-hand
   side by central or forward differences) and five quadratures: roll cos(w t), roll sin(w t),
   steer cos(w t), steer sin(w t) and tau. */

#include MODEL_C
#include "forcing.h"
#include "model_rhs.h"
#include "dopri_flow.h"

typedef struct {
    forcing_t f;          /* the pedalling forcing and the parameters (forcing.h) */
    double u_rear;        /* held rear-wheel rate */
    double omega_q;       /* frequency of the Fourier quadratures (the cadence) */
    double fd_step;       /* relative step of the directional differences */
    int central;          /* 1: central differences (2 evaluations per column), 0: forward */
    int nvar;             /* variational columns of the flow (set by po_flow) */
} po_forcing;

/* Reduced right-hand side at time t (exported for tests and the symmetry check). */
int po_rhs(const po_forcing *fc, double t, const double *y, double *dy, double *tau) {
    double s[64 * 3], tr, ts;
    pedal_forcing(&fc->f, t, s, &tr, &ts);
    return model_held_rhs(y, fc->u_rear, fc->f.p, s, tr, ts, dy, tau);
}

/* Pitch on the ground-contact manifold at (roll, steer), integrating the pitch rate of the
   velocity constraints along the straight path from upright (pitch0) with classical RK4, and
   its derivatives with respect to roll and steer at the end point. */
int po_pitch(const po_forcing *fc, double roll, double steer, double pitch0, int steps,
             double *pitch, double *dpitch) {
    double q[8] = {0}, u[8] = {0}, A[40], Ad[25], C[15];
    int piv[5];
    double p = pitch0, h = 1.0 / steps, k[4];
    for (int n = 0; n < steps; n++) {
        double s0 = n * h;
        double ss[4] = {s0, s0 + 0.5 * h, s0 + 0.5 * h, s0 + h};
        for (int st = 0; st < 4; st++) {
            double pp = p + (st == 0 ? 0.0 : (st == 3 ? h : 0.5 * h) * k[st - 1]);
            memset(q, 0, sizeof q); memset(u, 0, sizeof u);
            q[3] = ss[st] * roll; q[4] = pp; q[6] = ss[st] * steer;
            u[3] = roll; u[6] = steer;
            if (model_speeds(q, fc->f.p, u, A, Ad, piv, C)) return 1;
            k[st] = u[4];
        }
        p += h / 6.0 * (k[0] + 2 * k[1] + 2 * k[2] + k[3]);
    }
    *pitch = p;
    memset(q, 0, sizeof q); memset(u, 0, sizeof u);
    q[3] = roll; q[4] = p; q[6] = steer;
    if (model_speeds(q, fc->f.p, u, A, Ad, piv, C)) return 1;
    dpitch[0] = C[3 * 3 + 0];  /* d pitch rate / d roll rate: row pitch (U_DEP[3] = 4) */
    dpitch[1] = C[3 * 3 + 2];
    return 0;
}

/* Augmented right-hand side: state (5), nvar variational columns (5 each), quadratures (5). */
static int po_aug(const void *ctx, double t, const double *Y, double *dY) {
    const po_forcing *fc = (const po_forcing *)ctx;
    const int nvar = fc->nvar;
    double tau, yp[5], ym[5], fp[5], fm[5], s[64 * 3], tr, ts;
    pedal_forcing(&fc->f, t, s, &tr, &ts);
    if (model_held_rhs(Y, fc->u_rear, fc->f.p, s, tr, ts, dY, &tau)) return 1;
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
            if (model_held_rhs(yp, fc->u_rear, fc->f.p, s, tr, ts, fp, 0)
                || model_held_rhs(ym, fc->u_rear, fc->f.p, s, tr, ts, fm, 0)) return 1;
            for (int i = 0; i < 5; i++) out[i] = (fp[i] - fm[i]) / (2.0 * e);
        } else {
            if (model_held_rhs(yp, fc->u_rear, fc->f.p, s, tr, ts, fp, 0)) return 1;
            for (int i = 0; i < 5; i++) out[i] = (fp[i] - dY[i]) / e;
        }
    }
    double *qd = dY + 5 + 5 * nvar, c = cos(fc->omega_q * t), sn = sin(fc->omega_q * t);
    qd[0] = Y[0] * c; qd[1] = Y[0] * sn; qd[2] = Y[2] * c; qd[3] = Y[2] * sn; qd[4] = tau;
    return 0;
}

/* Flow from t0 to t1. Y0/Y1: augmented vectors (5 + 5 nvar + 5, quadratures start at Y0's).
   Error control on the five states only. h_io: initial step (<= 0: automatic), returns the last
   accepted step. peak: max |roll|, max |steer| at the steps. n_rhs: evaluations of the reduced
   right-hand side. Returns 0, or -1 non-finite/singular, -2 step underflow, -3 too many steps,
   -4 too many variational columns. */
int po_flow(po_forcing *fc, double t0, double t1, const double *Y0, int nvar, double rtol,
            const double *atol, double *Y1, double *peak, long *n_rhs, double *h_io) {
    static const int peak_index[2] = {0, 2};
    if (nvar < 0 || nvar > 8) return -4;
    fc->nvar = nvar;
    long calls = 0;
    int st = dopri_flow(po_aug, fc, 5 + 5 * nvar + 5, 5, t0, t1, Y0, rtol, atol, Y1, 2,
                        peak_index, peak, &calls, h_io);
    *n_rhs = calls * (1 + (fc->central ? 2 : 1) * nvar);
    return st;
}
