"""Time integration with fall events: one interface for LN, NT and NP (:mod:`.core`).

:func:`integrate` (a sampled run with terminal fall events) and :func:`flow` (the state at the
end of an interval) take a :class:`System` -- a model with its forcing that can evaluate its
right-hand side in Python and, optionally, in C -- and return a :class:`Simulation`. The C
integrator is ``dopri.c`` (Dormand-Prince 5(4)); ``linear_rhs.c`` is the right-hand side of the
linear models (:mod:`.linear`); the non-linear models' right-hand side is
``pedalrepro/nonlinear/rhs_driver.c`` (:mod:`pedalrepro.nonlinear.simulate`).
"""

from .core import (
    SPACAR_ATOL,
    SPACAR_RTOL,
    VARIANTS,
    CompiledRhs,
    Simulation,
    SimulationError,
    System,
    flow,
    harmonic_torque,
    integrate,
)
from .linear import LinearSystem

__all__ = ["SPACAR_ATOL", "SPACAR_RTOL", "VARIANTS", "CompiledRhs", "LinearSystem", "Simulation",
           "SimulationError", "System", "flow", "harmonic_torque", "integrate"]
