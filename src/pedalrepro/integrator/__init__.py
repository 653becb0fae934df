"""Time integration with fall events: one interface for LN, NT and NP (:mod:`.core`).

:func:`integrate` (a sampled run with terminal fall events) and :func:`flow` (the state at the
end of an interval) take a :class:`System` -- a model with its forcing that can evaluate its
right-hand side in Python and, optionally, in C -- and return a :class:`Simulation`. The C
integrator is ``pedalrepro/csrc/dopri_sampled.h`` (Dormand-Prince 5(4), the step of
``dopri.h``); ``linear_rhs.h`` is the right-hand side of the linear models (:mod:`.linear`), the
non-linear models' is ``model_rhs.h`` (:mod:`pedalrepro.nonlinear.simulate`); libraries are
built by :mod:`.build`.
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
