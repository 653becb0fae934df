"""One fall-event integrator for every time solution: LN (linear), NT and NP (non-linear).

The thesis integrated its SPACAR models with a Shampine-Gordon multistep method at SPACAR's
default local tolerances (abstol 1e-5, reltol 1e-4, Sec 3.1.2.1) and the linear models with
Matlab's ode45 (Dormand-Prince 5(4)); a run stopped when the bicycle fell. Here a run is one call
of :func:`integrate` on a :class:`System` with a terminal event at ``|roll| = fall angle`` (and
``|steer| = steer limit`` for a model whose arms stop reaching the handlebar): the part simulated
before the fall is kept, samples after it are NaN.

Two backends, one interface and one result type (:class:`Simulation`):

* compiled (``method="RK45"`` and a system with a compiled right-hand side): the whole run in C
  (``pedalrepro/csrc/dopri_sampled.h``), the Dormand-Prince pair of
  ``scipy.integrate.solve_ivp(method="RK45")``;
  ``variant="scipy"`` reproduces solve_ivp's RK45 step for step (step-size rules, quartic dense
  output, event location); ``variant="hermite"`` is the first compiled scheme, kept for the NT/NP
  sweeps (cubic Hermite samples, simplified initial step);
* Python: ``solve_ivp`` with ``system.rhs`` (any ``method``; the reference).
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

__all__ = [
    "SPACAR_RTOL", "SPACAR_ATOL", "VARIANTS", "MAX_STEPS", "SimulationError", "Simulation",
    "CompiledRhs", "System", "integrate", "flow", "harmonic_torque",
]

#: SPACAR's default local error tolerances used by the thesis (Sec 3.1.2.1).
SPACAR_RTOL = 1e-4
SPACAR_ATOL = 1e-5
#: Integrator variants of the compiled backend (see the module docstring).
VARIANTS: tuple[str, ...] = ("scipy", "hermite")
#: Largest number of accepted steps of one compiled run.
MAX_STEPS = 50_000_000
_STATUS = {-1: "non-finite state or singular system", -2: "step size underflow",
           -3: "too many steps", -4: "bad arguments (state size)"}


class SimulationError(RuntimeError):
    """The integration produced non-finite states or failed (not a fall: falls are events)."""


@dataclass
class Simulation:
    """One time solution.

    Attributes
    ----------
    t_s
        Output times (the full requested grid), s.
    roll_rad, steer_rad
        Roll and steer angles on ``t_s``; NaN after a fall.
    states
        The full state on ``t_s`` (one row per state), NaN after a fall.
    fell
        Whether a terminal event (fall, arm reach) ended the run.
    t_end_s
        Time the run ended (the event time, or the last requested time).
    n_rhs
        Number of right-hand-side evaluations (for benchmarks).
    """

    t_s: np.ndarray
    roll_rad: np.ndarray
    steer_rad: np.ndarray
    states: np.ndarray
    fell: bool
    t_end_s: float
    n_rhs: int


@dataclass
class CompiledRhs:
    """A right-hand side in C: the library (with the sampled loop of
    ``pedalrepro/csrc/dopri_sampled.h`` compiled in), the address of its
    ``int f(const void *ctx, double t, const double *x, double *dx)`` and the context.

    ``keep`` holds the arrays the context points to (they must outlive the calls).
    """

    lib: ctypes.CDLL
    function: int
    context: ctypes.Structure
    keep: list = field(default_factory=list)

    def evaluate(self, t: float, x: np.ndarray) -> np.ndarray:
        """``x'`` at time ``t`` and state ``x`` (NaN where the right-hand side failed)."""
        xa = np.ascontiguousarray(x, dtype=float)
        dx = np.empty_like(xa)
        status = self.lib.dopri_eval(self.function, ctypes.byref(self.context), float(t),
                                     xa.ctypes.data, dx.ctypes.data)
        if status:
            dx[:] = np.nan
        return dx


class System(Protocol):
    """What :func:`integrate` needs of a model with its forcing.

    ``rhs(t, x)``: the state derivative (Python; the reference); ``compiled()``: the same in C
    (:class:`CompiledRhs`) or None; ``roll_index``/``steer_index``: rows of roll and steer in the
    state; ``steer_limit_rad``: a second terminal event on ``|steer|`` (inf: none).
    """

    roll_index: int
    steer_index: int
    steer_limit_rad: float

    def rhs(self, t: float, x: np.ndarray) -> np.ndarray: ...

    def compiled(self) -> CompiledRhs | None: ...


class _Options(ctypes.Structure):
    _fields_ = [("rtol", ctypes.c_double), ("atol", ctypes.c_double),
                ("n_events", ctypes.c_int), ("event_index", ctypes.c_void_p),
                ("event_limit", ctypes.c_void_p), ("variant", ctypes.c_int),
                ("max_steps", ctypes.c_long)]


def _events(system: System, fall_roll_rad: float) -> list[tuple[int, float]]:
    events = [(system.roll_index, float(fall_roll_rad))]
    if np.isfinite(system.steer_limit_rad):
        events.append((system.steer_index, float(system.steer_limit_rad)))
    return events


def integrate(
    system: System,
    x0: np.ndarray,
    t_s: np.ndarray,
    *,
    rtol: float,
    atol: float,
    fall_roll_rad: float,
    method: str = "RK45",
    compiled: bool = True,
    variant: str = "scipy",
) -> Simulation:
    """Integrate ``system`` from ``x0`` at ``t_s[0]``, sampled at ``t_s``, until a fall.

    Parameters
    ----------
    system
        A :class:`System`: :class:`pedalrepro.integrator.linear.LinearSystem` (LN) or
        :class:`pedalrepro.nonlinear.simulate.ForcedModel` (NT, NP).
    x0
        Initial state.
    t_s
        Increasing sample times; the run covers ``[t_s[0], t_s[-1]]``. Two times
        ``[t0, t1]`` integrate over an interval without sampling in between.
    rtol, atol
        Local error tolerances (scipy's error norm; the thesis: ode45's 1e-3/1e-6 for LN,
        SPACAR's :data:`SPACAR_RTOL`/:data:`SPACAR_ATOL` for its non-linear runs).
    fall_roll_rad
        Terminal event: the run stops when ``|roll|`` reaches this angle (``inf``: never); also
        when ``|steer|`` reaches ``system.steer_limit_rad``.
    method
        ``"RK45"`` (compiled when available) or any ``solve_ivp`` method (Python).
    compiled
        False forces the Python backend.
    variant
        Compiled RK45 variant, one of :data:`VARIANTS`.

    Raises
    ------
    SimulationError
        The solver failed or a state became non-finite; the message names the time or reason.
    """
    t = np.ascontiguousarray(t_s, dtype=float)
    if t.ndim != 1 or t.size < 1 or np.any(np.diff(t) <= 0) or not np.all(np.isfinite(t)):
        raise ValueError("t_s must be finite and strictly increasing")
    if not (rtol > 0 and atol > 0 and np.isfinite(rtol) and np.isfinite(atol)):
        raise ValueError(f"rtol and atol must be finite and positive, got {rtol}, {atol}")
    if not fall_roll_rad > 0:
        raise ValueError(f"fall_roll_rad must be positive, got {fall_roll_rad}")
    if variant not in VARIANTS:
        raise ValueError(f"unknown integrator variant {variant!r}: expected one of {VARIANTS}")
    x0 = np.ascontiguousarray(x0, dtype=float)
    c = system.compiled() if compiled and method == "RK45" else None
    if c is not None:
        return _integrate_compiled(system, c, x0, t, rtol, atol, fall_roll_rad, variant)
    return _integrate_python(system, x0, t, rtol, atol, fall_roll_rad, method)


def flow(system: System, x0: np.ndarray, t0_s: float, t1_s: float, *, rtol: float,
         atol: float, method: str = "RK45", variant: str = "scipy") -> np.ndarray:
    """The state at ``t1_s`` from ``x0`` at ``t0_s`` (no fall event, no samples in between).

    For shooting methods (periodic orbits): one compiled run per call when available.
    """
    sim = integrate(system, x0, np.array([t0_s, t1_s], float), rtol=rtol, atol=atol,
                    fall_roll_rad=np.inf, method=method, variant=variant)
    return sim.states[:, -1].copy()


def _result(system: System, t: np.ndarray, states: np.ndarray, fell: bool, t_end: float,
            n_rhs: int) -> Simulation:
    return Simulation(t, states[system.roll_index].copy(), states[system.steer_index].copy(),
                      states, bool(fell), float(t_end), int(n_rhs))


def _integrate_compiled(system, c: CompiledRhs, x0, t, rtol, atol, fall_roll_rad,
                        variant) -> Simulation:
    events = _events(system, fall_roll_rad)
    index = np.array([e[0] for e in events], dtype=np.intc)
    limit = np.array([e[1] for e in events], dtype=float)
    opts = _Options(rtol, atol, len(events), index.ctypes.data, limit.ctypes.data,
                    VARIANTS.index(variant), MAX_STEPS)
    out = np.empty((x0.size, t.size))
    t_end, n_rhs = ctypes.c_double(0.0), ctypes.c_long(0)
    status = c.lib.dopri_integrate(c.function, ctypes.byref(c.context), x0.size, x0.ctypes.data,
                                   t.ctypes.data, t.size, ctypes.byref(opts), out.ctypes.data,
                                   ctypes.byref(t_end), ctypes.byref(n_rhs))
    if status < 0:
        raise SimulationError(f"compiled integration failed: {_STATUS[status]}")
    return _result(system, t, out, status == 1, t_end.value, n_rhs.value)


def _integrate_python(system, x0, t, rtol, atol, fall_roll_rad, method) -> Simulation:
    from scipy.integrate import solve_ivp  # the reference path only (0.6 s import)

    def guarded(tt, x):
        dx = system.rhs(tt, x)
        if not np.all(np.isfinite(dx)):
            raise SimulationError(f"non-finite state derivative at t = {tt:.6g} s (state {x})")
        return dx

    def terminal(index: int, limit: float) -> Callable:
        def event(tt, x):
            return limit - abs(x[index])

        event.terminal = True
        event.direction = -1
        return event

    events = [terminal(i, lim) for i, lim in _events(system, fall_roll_rad)]
    sol = solve_ivp(guarded, (t[0], t[-1]), x0, method=method, t_eval=t, rtol=rtol, atol=atol,
                    events=events)
    if sol.status == -1:
        raise SimulationError(f"integration failed: {sol.message}")
    if not np.all(np.isfinite(sol.y)):
        raise SimulationError("non-finite states")
    states = np.full((x0.size, t.size), np.nan)
    states[:, : sol.y.shape[1]] = sol.y
    fell = sol.status == 1
    t_end = float(min(e[0] for e in sol.t_events if len(e))) if fell else float(t[-1])
    return _result(system, t, states, fell, t_end, sol.nfev)


def harmonic_torque(harmonics, omega_rad_s: float) -> Callable[[float], tuple[float, float]]:
    """Generalised pedalling torques of Eq 3.14 as a function of time.

    ``f(t) = Re( sum_k coef[k] (n[k] omega)^2 exp(i n[k] omega t) )`` for roll and steer, with
    ``harmonics`` a :class:`pedalrepro.disturbance.TorqueHarmonics` (``n``, ``roll``, ``steer``).
    """
    n = np.asarray(harmonics.n, dtype=float)
    w = n * omega_rad_s
    roll = np.asarray(harmonics.roll, dtype=complex) * w**2
    steer = np.asarray(harmonics.steer, dtype=complex) * w**2
    coef = np.vstack([roll, steer])

    def torque(t: float) -> tuple[float, float]:
        e = np.exp(1j * w * t)
        r, s = (coef @ e).real
        return float(r), float(s)

    return torque
