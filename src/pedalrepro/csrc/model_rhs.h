/* The constrained right-hand side of a non-linear model (pedalrepro.nonlinear), in null-space
   form, with the held-wheel-rate variant of the periodic orbits. Include after the model's
   generated constraint_matrix(q, p, A) and dynamics(q, u, p, s, M, F, b)
   (pedalrepro.nonlinear.codegen).

   Dependent speeds from A u = 0, then Kane's equations reduced to the three independent speeds
   (the null-space form of the Lagrange-multiplier system [M A^T; A 0] [u'; lam] = [F; -b]:
   with u_dep = C u_ind, C = -A_dep^-1 A_ind, the accelerations u' = B u'_ind + e, B = [I; C],
   e = [0; -A_dep^-1 b], satisfy (B^T M B) u'_ind = B^T (F - M e), since A B = 0). One LU
   factorisation of A_dep serves the speeds and the accelerations; the reduced system is 3 x 3
   instead of 13 x 13. The Python reference (NonlinearModel.accelerations) solves the 13 x 13
   system: the two agree to rounding (tests/nonlinear/test_nonlinear.py).

   Simulation state x = [roll, pitch, steer, u_roll, u_rear, u_steer] (model_rhs). Periodic
   orbits hold the rear-wheel rate (model_held_rhs): state y = [roll, pitch, steer, u_roll,
   u_steer], and a generalised force tau on the rear-wheel rotation (a hub torque) chosen so that
   the rear-wheel acceleration is zero; with u'_rear = 0 known, rows roll and steer of the reduced
   system give the two accelerations and row rear wheel gives tau. */
#ifndef PEDALREPRO_MODEL_RHS_H
#define PEDALREPRO_MODEL_RHS_H

#include <math.h>
#include "lu.h"

/* Coordinates and speeds: q[3] roll, q[4] pitch, q[6] steer; independent speeds u[3] roll,
   u[5] rear wheel, u[6] steer (pedalrepro.nonlinear.symbolic ROLL, PITCH, STEER, REAR_WHEEL). */
static const int U_IND[3] = {3, 5, 6};
static const int U_DEP[5] = {0, 1, 2, 4, 7};

/* Dependent speeds u[U_DEP] = C u[U_IND] from A(q) u = 0: A (5 x 8), the factors of A_dep
   (Ad, piv) and C = -A_dep^-1 A_ind (5 x 3) returned. */
static int model_speeds(const double *q, const double *p, double *u, double *A, double *Ad,
                        int *piv, double *C) {
    constraint_matrix(q, p, A);
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) Ad[i * 5 + j] = A[i * 8 + U_DEP[j]];
    if (lu_factor(5, Ad, piv)) return 1;
    for (int i = 0; i < 5; i++)                         /* C = -A_dep^-1 A_ind */
        for (int k = 0; k < 3; k++) C[i * 3 + k] = -A[i * 8 + U_IND[k]];
    lu_solve_columns(5, 3, Ad, piv, C);
    for (int j = 0; j < 5; j++) {
        double acc = 0.0;
        for (int k = 0; k < 3; k++) acc += C[j * 3 + k] * u[U_IND[k]];
        u[U_DEP[j]] = acc;
    }
    return 0;
}

/* The reduced system R u'_ind = r (R = B^T M B, 3 x 3; r = B^T (F - M e)) at state x with
   generalised forces t_roll, t_rear, t_steer on the independent speeds; u: all eight speeds. */
static int model_reduced(const double *x, const double *p, const double *s, double t_roll,
                         double t_rear, double t_steer, double *R, double *r, double *u) {
    double q[8] = {0}, A[40], M[64], F[8], b[5];
    for (int i = 0; i < 8; i++) u[i] = 0.0;
    q[3] = x[0]; q[4] = x[1]; q[6] = x[2];
    u[3] = x[3]; u[5] = x[4]; u[6] = x[5];
    double Ad[25], C[15];
    int piv[5];
    if (model_speeds(q, p, u, A, Ad, piv, C)) return 1;
    dynamics(q, u, p, s, M, F, b);
    F[3] += t_roll; F[6] += t_steer;
    if (t_rear != 0.0) F[5] += t_rear;
    double B[24] = {0}, e[8] = {0}, d[5];
    for (int i = 0; i < 5; i++) d[i] = -b[i];
    lu_solve(5, Ad, piv, d);                            /* u'_dep = C u'_ind + d */
    for (int k = 0; k < 3; k++) B[U_IND[k] * 3 + k] = 1.0;
    for (int j = 0; j < 5; j++) {
        for (int k = 0; k < 3; k++) B[U_DEP[j] * 3 + k] = C[j * 3 + k];
        e[U_DEP[j]] = d[j];
    }
    double MB[24], g[8];
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
    return 0;
}

/* Simulation right-hand side: x' at state x (6) with roll, rear-hub and steer torques; u_out
   (optional): the eight speeds. Returns 0 on success. */
static int model_rhs(const double *x, const double *p, const double *s, double t_roll,
                     double t_rear, double t_steer, double *dx, double *u_out) {
    double R[9], r[3], u[8];
    int st = model_reduced(x, p, s, t_roll, t_rear, t_steer, R, r, u);
    if (st) return st;
    int piv3[3];
    if (lu_factor(3, R, piv3)) return 2;
    lu_solve(3, R, piv3, r);
    dx[0] = u[3]; dx[1] = u[4]; dx[2] = u[6];
    dx[3] = r[0]; dx[4] = r[1]; dx[5] = r[2];
    if (u_out) for (int i = 0; i < 8; i++) u_out[i] = u[i];
    for (int i = 0; i < 6; i++) if (!isfinite(dx[i])) return 3;
    return 0;
}

/* Held-wheel-rate right-hand side: y' (5) at y = [roll, pitch, steer, u_roll, u_steer] with the
   rear-wheel rate u_rear held; tau (optional): the holding hub torque. Returns 0 on success. */
static int model_held_rhs(const double *y, double u_rear, const double *p, const double *s,
                          double t_roll, double t_steer, double *dy, double *tau) {
    const double x[6] = {y[0], y[1], y[2], y[3], u_rear, y[4]};
    double R[9], r[3], u[8];
    int st = model_reduced(x, p, s, t_roll, 0.0, t_steer, R, r, u);
    if (st) return st;
    double R2[4] = {R[0], R[2], R[6], R[8]}, a[2] = {r[0], r[2]};
    int piv2[2];
    if (lu_factor(2, R2, piv2)) return 2;
    lu_solve(2, R2, piv2, a);
    dy[0] = u[3]; dy[1] = u[4]; dy[2] = u[6];
    dy[3] = a[0]; dy[4] = a[1];
    if (tau) *tau = R[3] * a[0] + R[5] * a[1] - r[1];
    for (int i = 0; i < 5; i++) if (!isfinite(dy[i])) return 3;
    return 0;
}

#endif
