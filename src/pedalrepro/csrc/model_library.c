/* The simulation library of a non-linear model (pedalrepro.nonlinear.library): the model's
   generated code (MODEL_C, its file name given with -D and found on the -I path), the forcing,
   the null-space right-hand side and the sampled Dormand-Prince loop with fall events.
   Python side: pedalrepro.nonlinear.simulate.ForcedModel. */

#include MODEL_C
#include "forcing.h"
#include "model_rhs.h"
#include "dopri_sampled.h"

/* x' at state x = [roll, pitch, steer, u_roll, u_rear, u_steer] with roll and steer torques;
   u_out (optional): the eight speeds. Returns 0 on success. */
int full_rhs(const double *x, const double *p, const double *s, double t_roll, double t_steer,
             double *dx, double *u_out) {
    return model_rhs(x, p, s, t_roll, 0.0, t_steer, dx, u_out);
}

/* The forced right-hand side for the sampled loop: harmonic roll/steer torques (Eq 3.14)
   and/or prescribed leg motion given as Fourier series. */
int forced_rhs(const void *ctx, double t, const double *x, double *dx) {
    const forcing_t *fc = (const forcing_t *)ctx;
    double tr, ts, s[64 * 3];
    pedal_forcing(fc, t, s, &tr, &ts);
    return model_rhs(x, fc->p, s, tr, 0.0, ts, dx, 0);
}

/* forced_rhs with a rear-hub torque t_rear added (tests: the orbits' held-wheel-rate
   right-hand side equals this one at its holding torque). */
int forced_rhs_hub(const forcing_t *fc, double t, const double *x, double t_rear, double *dx) {
    double tr, ts, s[64 * 3];
    pedal_forcing(fc, t, s, &tr, &ts);
    return model_rhs(x, fc->p, s, tr, t_rear, ts, dx, 0);
}
