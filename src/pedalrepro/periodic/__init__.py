"""Periodic pedalling responses of the non-linear models: shooting, Floquet multipliers and
continuation (beyond the thesis).

The thesis estimates the pedalling response of its non-linear models (methods NT and NP,
Sec 3.1.2.1) from 180 s simulations reduced by a Hann-windowed DFT; where the bicycle is
unstable the runs fall and the estimate breaks down. Its own recommendation (Sec 3.2.4) is
numerical continuation of the periodic solutions (Doedel et al. 2003). This subpackage computes
those solutions directly:

* :mod:`.solver`: the shooting problem of one model, method and cadence (:class:`OrbitSolver`,
  :class:`Orbit`, :func:`orbit`) on the compiled held-speed right-hand side
  (``pedalrepro/csrc/periodic_library.c``);
* :mod:`.maps`: orbits over the speed x cadence grid (:func:`orbit_map`, :func:`write_map`);
* :mod:`.continuation`: branches in speed, cadence or torque scale (:func:`continue_branch`,
  :class:`Branch`, :func:`write_branches`);
* :mod:`.tables`: the summary tables of ``rules/periodic.smk`` (:func:`write_tables`).

The command line ``pedalrepro periodic`` is in :mod:`pedalrepro.cli`; the figures are in
:mod:`pedalrepro.figures.periodic`, registered in :mod:`pedalrepro.figures.registry`.
"""

from .continuation import Branch, continue_branch, write_branches
from .maps import MAP_KEYS, nested, orbit_map, write_map, write_submap
from .solver import (
    CADENCE_RANGE_RPM,
    LATERAL,
    METHODS,
    SPEED_RANGE_M_S,
    ConvergenceError,
    Orbit,
    OrbitSolver,
    orbit,
)
from .tables import crossing_table, map_summary, simulation_comparison, write_tables

__all__ = ["CADENCE_RANGE_RPM", "LATERAL", "MAP_KEYS", "METHODS", "SPEED_RANGE_M_S", "Branch",
           "ConvergenceError", "Orbit", "OrbitSolver", "continue_branch", "crossing_table",
           "map_summary", "nested", "orbit", "orbit_map", "simulation_comparison",
           "write_branches", "write_map", "write_submap", "write_tables"]
