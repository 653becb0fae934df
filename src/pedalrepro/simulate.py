"""Time integration of the non-linear bicycle-rider models with fall events (Sec 3.1.2.1).

The thesis integrated its SPACAR models with a Shampine-Gordon multistep method at SPACAR's
default local tolerances (abstol 1e-5, reltol 1e-4, Sec 3.1.2.1); a run stopped when the bicycle
fell and was repeated with shorter horizons. Here a run is one ``scipy.integrate.solve_ivp``
call with a terminal event at ``|roll| = fall angle``: the part simulated before the fall is
kept, samples after it are NaN. The tolerances are configuration values (``nonlinear.rtol``,
``nonlinear.atol``); the SPACAR values are available as ``nonlinear.spacar_rtol``/``_atol``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

#: SPACAR's default local error tolerances used by the thesis (Sec 3.1.2.1).
SPACAR_RTOL = 1e-4
SPACAR_ATOL = 1e-5


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
        The full state on ``t_s`` (rows: see :mod:`pedalrepro.nonlinear.numeric`), NaN after a fall.
    fell
        Whether the fall event ended the run.
    t_end_s
        Time the run ended (the fall time, or the requested duration).
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


def simulate(
    model,
    speed_m_s: float,
    duration_s: float,
    sample_rate_hz: float,
    *,
    torque: Callable[[float], tuple[float, float]] | None = None,
    x0: np.ndarray | None = None,
    rtol: float = 1e-6,
    atol: float = 1e-8,
    fall_roll_rad: float = 1.0,
    method: str = "RK45",
    rhs: Callable | None = None,
) -> Simulation:
    """Integrate a non-linear model from upright straight-ahead motion.

    Parameters
    ----------
    model
        A :class:`pedalrepro.nonlinear.numeric.NonlinearModel` (``rhs``, ``upright_state``).
    speed_m_s
        Initial forward speed (rear wheel rolling), m/s; roll, steer and their rates start at
        zero (Sec 3.1.2.2: zero initial conditions) unless ``x0`` is given.
    duration_s, sample_rate_hz
        Output grid ``t = 0, 1/fs, ...`` with ``round(duration * fs) + 1`` points.
    torque
        ``t -> (roll torque, steer torque)`` (N m), e.g. :func:`harmonic_torque`.
    rtol, atol
        Local error tolerances (SPACAR: :data:`SPACAR_RTOL`, :data:`SPACAR_ATOL`).
    fall_roll_rad
        Terminal event: the run stops when ``|roll|`` reaches this angle (and, for a model with
        arm loops, when ``|steer|`` reaches ``model.steer_limit_rad``: the arms' reach).
    rhs
        Optional replacement ``f(t, x)`` for ``model.rhs`` with the torque applied.

    Raises
    ------
    SimulationError
        When the solver fails or a state becomes non-finite; the message names the time.
    """
    if duration_s <= 0 or sample_rate_hz <= 0:
        raise ValueError("duration_s and sample_rate_hz must be positive")
    n_t = int(round(duration_s * sample_rate_hz)) + 1
    t_s = np.arange(n_t) / sample_rate_hz
    x0 = model.upright_state(speed_m_s) if x0 is None else np.asarray(x0, dtype=float)
    if rhs is None:
        if torque is None:
            def rhs(t, x):
                return model.rhs(t, x)
        else:
            def rhs(t, x):
                return model.rhs(t, x, torque(t))

    def guarded(t, x):
        dx = rhs(t, x)
        if not np.all(np.isfinite(dx)):
            raise SimulationError(f"non-finite state derivative at t = {t:.6g} s (state {x})")
        return dx

    def fall(t, x):
        return fall_roll_rad - abs(x[0])

    fall.terminal = True
    fall.direction = -1
    events = [fall]
    steer_limit = float(getattr(model, "steer_limit_rad", np.inf))
    if np.isfinite(steer_limit):
        # arm loops (model CF): beyond this steer angle the arms cannot reach the handlebar
        def reach(t, x):
            return steer_limit - abs(x[2])

        reach.terminal = True
        reach.direction = -1
        events.append(reach)
    sol = solve_ivp(guarded, (0.0, t_s[-1]), x0, method=method, t_eval=t_s, rtol=rtol,
                    atol=atol, events=events)
    if sol.status == -1:
        raise SimulationError(f"integration failed at speed {speed_m_s} m/s: {sol.message}")
    fell = sol.status == 1
    states = np.full((len(x0), n_t), np.nan)
    states[:, : sol.y.shape[1]] = sol.y
    if not np.all(np.isfinite(sol.y)):
        raise SimulationError(f"non-finite states at speed {speed_m_s} m/s")
    t_end = (float(min(e[0] for e in sol.t_events if len(e))) if fell else float(t_s[-1]))
    steer = states[2].copy() if len(x0) > 2 else np.full(n_t, np.nan)
    return Simulation(t_s, states[0].copy(), steer, states, fell, t_end, sol.nfev)


def simulate_compiled(
    model,
    speed_m_s: float,
    duration_s: float,
    sample_rate_hz: float,
    *,
    harmonics=None,
    omega_rad_s: float = 0.0,
    x0: np.ndarray | None = None,
    rtol: float = 1e-6,
    atol: float = 1e-8,
    fall_roll_rad: float = 1.0,
) -> Simulation:
    """:func:`simulate` with the whole run in compiled code (about 30 times faster).

    The same Dormand-Prince 5(4) pair and error norm as ``solve_ivp(method="RK45")``; output
    samples by cubic Hermite interpolation between steps; the fall event located by bisection.
    The forcing is given as data (not Python callables): ``harmonics`` at ``omega_rad_s``
    (Eq 3.14) and/or the model's prescribed leg motion (``model.spec``, a
    :class:`pedalrepro.nonlinear.prescribed.FourierSpec`).

    Raises
    ------
    SimulationError
        Non-finite state, step size underflow or a singular system.
    """
    import ctypes

    lib = model._lib
    if lib is None:
        raise SimulationError("no compiled library for this model (no C compiler?)")
    if duration_s <= 0 or sample_rate_hz <= 0:
        raise ValueError("duration_s and sample_rate_hz must be positive")
    n_t = int(round(duration_s * sample_rate_hz)) + 1
    t_s = np.arange(n_t) / sample_rate_hz
    x0 = model.upright_state(speed_m_s) if x0 is None else np.asarray(x0, dtype=float)
    dp, ci, cd = ctypes.c_void_p, ctypes.c_int, ctypes.c_double

    class Forcing(ctypes.Structure):
        _fields_ = [("n_harm", ci), ("harm_w", dp), ("roll_re", dp), ("roll_im", dp),
                    ("steer_re", dp), ("steer_im", dp), ("n_spec", ci), ("n_four", ci),
                    ("omega", cd), ("four_re", dp), ("four_im", dp), ("slope", dp), ("p", dp),
                    ("steer_limit", cd)]

    keep = []  # arrays referenced by pointer must outlive the call

    def ptr(a):
        a = np.ascontiguousarray(a, dtype=float)
        keep.append(a)
        return a.ctypes.data

    fc = Forcing()
    if harmonics is not None and omega_rad_s > 0:
        n = np.asarray(harmonics.n, dtype=float)
        w = n * omega_rad_s
        roll = np.asarray(harmonics.roll, dtype=complex) * w**2
        steer = np.asarray(harmonics.steer, dtype=complex) * w**2
        fc.n_harm = len(n)
        fc.harm_w, fc.roll_re, fc.roll_im = ptr(w), ptr(roll.real), ptr(roll.imag)
        fc.steer_re, fc.steer_im = ptr(steer.real), ptr(steer.imag)
    if model.n_spec:
        spec = model.spec
        fc.n_spec, fc.n_four, fc.omega = model.n_spec, spec.coef.shape[1], spec.omega_rad_s
        fc.four_re, fc.four_im = ptr(spec.coef.real), ptr(spec.coef.imag)
        fc.slope = ptr(spec.slope)
    fc.p = ptr(model._p_arr)
    fc.steer_limit = float(getattr(model, "steer_limit_rad", np.inf))
    lib.integrate.argtypes = [ctypes.POINTER(Forcing), dp, dp, ci, cd, cd, cd, dp,
                              ctypes.POINTER(cd), ctypes.POINTER(ctypes.c_long)]
    lib.integrate.restype = ci
    out = np.empty((6, n_t))
    t_end, n_rhs = cd(0.0), ctypes.c_long(0)
    status = lib.integrate(ctypes.byref(fc), ptr(x0), ptr(t_s), n_t, rtol, atol, fall_roll_rad,
                           out.ctypes.data, ctypes.byref(t_end), ctypes.byref(n_rhs))
    if status < 0:
        why = {-1: "non-finite state or singular system", -2: "step size underflow",
               -3: "too many steps"}[status]
        raise SimulationError(f"compiled integration failed at speed {speed_m_s} m/s: {why}")
    fell = status == 1
    steer = out[2].copy()
    return Simulation(t_s, out[0].copy(), steer, out, fell, float(t_end.value), int(n_rhs.value))
