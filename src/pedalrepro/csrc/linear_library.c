/* The linear models' library (pedalrepro.integrator.linear): their right-hand side and the
   sampled Dormand-Prince loop with fall events. */

#include "linear_rhs.h"
#include "dopri_sampled.h"
