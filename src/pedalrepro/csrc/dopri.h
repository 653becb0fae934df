/* The Dormand-Prince 5(4) pair (the scheme of scipy's RK45 and MATLAB's ode45): its tableau,
   written once, and one step. Two loops drive it: the sampled loop with fall events of the time
   solutions (dopri_sampled.h) and the flow loop of the periodic orbits with their variational
   equations and quadratures (dopri_flow.h). */
#ifndef PEDALREPRO_DOPRI_H
#define PEDALREPRO_DOPRI_H

#include <math.h>

/* Largest state of the sampled loop; the flow loop's augmented state (DOPRI_FLOW_NMAX). */
#define DOPRI_NMAX 32
#define DOPRI_FLOW_NMAX 64

typedef int (*dopri_rhs)(const void *ctx, double t, const double *x, double *dx);

static const double DP_C2 = 1.0 / 5, DP_C3 = 3.0 / 10, DP_C4 = 4.0 / 5, DP_C5 = 8.0 / 9;
static const double DP_A21 = 1.0 / 5;
static const double DP_A31 = 3.0 / 40, DP_A32 = 9.0 / 40;
static const double DP_A41 = 44.0 / 45, DP_A42 = -56.0 / 15, DP_A43 = 32.0 / 9;
static const double DP_A51 = 19372.0 / 6561, DP_A52 = -25360.0 / 2187, DP_A53 = 64448.0 / 6561, DP_A54 = -212.0 / 729;
static const double DP_A61 = 9017.0 / 3168, DP_A62 = -355.0 / 33, DP_A63 = 46732.0 / 5247, DP_A64 = 49.0 / 176, DP_A65 = -5103.0 / 18656;
static const double DP_B1 = 35.0 / 384, DP_B3 = 500.0 / 1113, DP_B4 = 125.0 / 192, DP_B5 = -2187.0 / 6784, DP_B6 = 11.0 / 84;
static const double DP_E1 = 71.0 / 57600, DP_E3 = -71.0 / 16695, DP_E4 = 71.0 / 1920, DP_E5 = -17253.0 / 339200, DP_E6 = 22.0 / 525, DP_E7 = -1.0 / 40;
/* scipy's RK45.P (quartic dense output), rows = stages */
static const double DP_P[7][4] = {
    {1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0, -12715105075.0 / 11282082432.0},
    {0.0, 0.0, 0.0, 0.0},
    {0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0, 87487479700.0 / 32700410799.0},
    {0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0, -10690763975.0 / 1880347072.0},
    {0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0, 701980252875.0 / 199316789632.0},
    {0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0, -1453857185.0 / 822651844.0},
    {0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0}};

/* Stages of one step of size h from (t, y) with f0 = f(t, y): k[0] = f0 (given), k[1..6] the
   other stages (k[6] = f(t + h, yn), first same as last), yn the fifth-order solution.
   tmp: n scratch. Returns nonzero when the right-hand side failed. */
static int dopri_step(dopri_rhs f, const void *ctx, int n, double t, double h, const double *y,
                      double *const k[7], double *yn, double *tmp) {
    const double *f0 = k[0];
    double *k2 = k[1], *k3 = k[2], *k4 = k[3], *k5 = k[4], *k6 = k[5], *k7 = k[6];
    for (int i = 0; i < n; i++) tmp[i] = y[i] + h * DP_A21 * f0[i];
    if (f(ctx, t + DP_C2 * h, tmp, k2)) return 1;
    for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (DP_A31 * f0[i] + DP_A32 * k2[i]);
    if (f(ctx, t + DP_C3 * h, tmp, k3)) return 1;
    for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (DP_A41 * f0[i] + DP_A42 * k2[i] + DP_A43 * k3[i]);
    if (f(ctx, t + DP_C4 * h, tmp, k4)) return 1;
    for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (DP_A51 * f0[i] + DP_A52 * k2[i] + DP_A53 * k3[i] + DP_A54 * k4[i]);
    if (f(ctx, t + DP_C5 * h, tmp, k5)) return 1;
    for (int i = 0; i < n; i++) tmp[i] = y[i] + h * (DP_A61 * f0[i] + DP_A62 * k2[i] + DP_A63 * k3[i] + DP_A64 * k4[i] + DP_A65 * k5[i]);
    if (f(ctx, t + h, tmp, k6)) return 1;
    for (int i = 0; i < n; i++) yn[i] = y[i] + h * (DP_B1 * f0[i] + DP_B3 * k3[i] + DP_B4 * k4[i] + DP_B5 * k5[i] + DP_B6 * k6[i]);
    if (f(ctx, t + h, yn, k7)) return 1;
    return 0;
}

/* Local error estimate of component i of the step (fifth minus embedded fourth order). */
static inline double dopri_error(double h, double *const k[7], int i) {
    return h * (DP_E1 * k[0][i] + DP_E3 * k[2][i] + DP_E4 * k[3][i] + DP_E5 * k[4][i] + DP_E6 * k[5][i] + DP_E7 * k[6][i]);
}

#endif
