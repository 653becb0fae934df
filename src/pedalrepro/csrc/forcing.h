/* The pedalling forcing of the non-linear models, included by the simulation library
   (model_library.c) and the periodic-orbit library (periodic_library.c). Filled from Python by
   one builder: pedalrepro.csrc.forcing_struct (its ctypes mirror ForcingStruct).

   Harmonic roll and steer torques (Eq 3.14: coefficients times w^2, sum of Re(c e^{i w t})) and
   prescribed leg motion given as Fourier series plus a linear drift (n_spec / 3 signals: value,
   rate and acceleration in s). */

#ifndef PEDALREPRO_FORCING_H
#define PEDALREPRO_FORCING_H

#include <math.h>

typedef struct {
    int n_harm; const double *harm_w; const double *roll_re; const double *roll_im;
    const double *steer_re; const double *steer_im;          /* torque coefficients * w^2 */
    int n_spec; int n_four; double omega; const double *four_re; const double *four_im;
    const double *slope;                                       /* spec: n_spec/3 signals */
    const double *p;                                           /* the model's parameters */
} forcing_t;

/* Forcing at time t: prescribed motion s (when n_spec > 0) and the roll and steer torques.
   The Fourier coefficients are stored harmonic by harmonic (four_re[n * m + i] for signal i of
   m = n_spec / 3), so that the loop over the signals runs on contiguous memory and vectorises;
   s is restrict (it never overlaps the coefficients). Each signal sums its terms in the order
   n = 0, 1, ... */
static void pedal_forcing(const forcing_t *fc, double t, double *restrict s, double *tr,
                          double *ts) {
    *tr = 0.0; *ts = 0.0;
    for (int k = 0; k < fc->n_harm; k++) {
        double c = cos(fc->harm_w[k] * t), sn = sin(fc->harm_w[k] * t);
        *tr += fc->roll_re[k] * c - fc->roll_im[k] * sn;
        *ts += fc->steer_re[k] * c - fc->steer_im[k] * sn;
    }
    int m = fc->n_spec / 3;
    if (m <= 0) return;
    double *restrict pos = s, *restrict vel = s + m, *restrict acc = s + 2 * m;
    for (int i = 0; i < m; i++) { pos[i] = fc->slope[i] * t; vel[i] = fc->slope[i]; acc[i] = 0.0; }
    double c1 = cos(fc->omega * t), s1 = sin(fc->omega * t), c = 1.0, sn = 0.0;
    for (int n = 0; n < fc->n_four; n++) {
        double wn = n * fc->omega;
        if (n > 0) { double cn = c * c1 - sn * s1; sn = sn * c1 + c * s1; c = cn; }
        const double *restrict re = fc->four_re + n * m, *restrict im = fc->four_im + n * m;
        for (int i = 0; i < m; i++) {
            double val = re[i] * c - im[i] * sn;        /* Re(coef e^{i wn t}) */
            pos[i] += val;
            vel[i] += -wn * (re[i] * sn + im[i] * c);   /* Re(i wn coef e^{...}) */
            acc[i] += -wn * wn * val;
        }
    }
}

#endif
