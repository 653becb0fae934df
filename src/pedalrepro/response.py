"""Response of the linear models to the pedalling torques (Sec 3.1.2.1, 3.1.2.2, Eq 3.8-3.18).

The pedalling disturbance is a sum of harmonics (Eq 3.14, ``pedalrepro.disturbance``)::

    f(t) = Re( sum_k coef[k] (n_k w)^2 exp(i n_k w t) )

so the particular solution (Eq 3.10-3.15) is ``q_p(t) = Re( sum_k Q_k exp(i n_k w t) )`` with

    [ -(n w)^2 M + i n w v C1 + g K0 + v^2 K2 ] Q_k = coef[k] (n w)^2.

This module solves that for whole speed x cadence grids in one batched complex solve, adds the
homogeneous solution for zero initial state (the analytic time solution "LA", Eq 3.9, 3.16-3.18)
and integrates the same linear model numerically ("LN", the thesis's ode45 check) with a fall
event.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from . import spectral
from .integrator import LinearSystem, SimulationError, integrate
from .linear import state_matrix
from .params import LinearModel

__all__ = [
    "Harmonics", "SimpleHarmonics", "select", "harmonic_coefficients", "dynamic_stiffness",
    "particular_solution", "solve_2x2", "particular_solution_loop", "superposed_amplitude",
    "TimeSolution", "analytic_time_solution", "numerical_time_solution", "numerical_time_solutions",
    "cadence_amplitudes", "grid", "speed_cadence_grid", "time_samples", "forcing",
]


class Harmonics(Protocol):
    """Anything like ``disturbance.TorqueHarmonics``: harmonic numbers and complex coefficients.

    ``n`` (k,), ``roll``, ``steer`` (k,) complex, N m s^2 (Eq 3.14 without ``(n w)^2``).
    """

    n: np.ndarray
    roll: np.ndarray
    steer: np.ndarray


@dataclass(frozen=True)
class SimpleHarmonics:
    """A plain :class:`Harmonics` (for tests, subsets of harmonics and the CAM variants)."""

    n: np.ndarray
    roll: np.ndarray
    steer: np.ndarray


def select(harmonics: Harmonics, n: tuple[int, ...] | None = None, *, roll: bool = True,
           steer: bool = True) -> SimpleHarmonics:
    """A subset of the harmonics (e.g. ``n=(1,)`` for the cadence-only torque ``T(w)``).

    ``steer=False`` keeps only the roll torque (the "roll torque only" case of Fig 3.30).
    """
    nn = np.asarray(harmonics.n, dtype=int)
    keep = np.ones(len(nn), bool) if n is None else np.isin(nn, n)
    if not keep.any():
        raise ValueError(f"none of the harmonics {n} in {nn.tolist()}")
    r = np.asarray(harmonics.roll, complex)[keep] * (1.0 if roll else 0.0)
    s = np.asarray(harmonics.steer, complex)[keep] * (1.0 if steer else 0.0)
    return SimpleHarmonics(nn[keep], r, s)


def harmonic_coefficients(harmonics: Harmonics) -> tuple[np.ndarray, np.ndarray]:
    """Harmonic numbers ``n`` (k,) and torque coefficients (k, 2) [roll, steer] (Eq 3.14).

    Raises ``ValueError`` unless ``n``, ``roll`` and ``steer`` are 1-D of equal length.
    """
    n = np.asarray(harmonics.n, dtype=float)
    coef = np.stack([np.asarray(harmonics.roll, complex), np.asarray(harmonics.steer, complex)],
                    axis=-1)
    if n.ndim != 1 or coef.shape != (len(n), 2):
        raise ValueError("harmonics must have 1-D n, roll, steer of equal length")
    return n, coef


def dynamic_stiffness(model: LinearModel, speed_m_s, frequency_rad_s) -> np.ndarray:
    """``-w^2 M + i w v C1 + g K0 + v^2 K2`` for broadcast speeds and frequencies, (..., 2, 2)."""
    v = np.asarray(speed_m_s, dtype=float)[..., None, None]
    w = np.asarray(frequency_rad_s, dtype=float)[..., None, None]
    return (-(w**2) * model.M + 1j * w * v * model.C1 + model.g * model.K0
            + v**2 * model.K2)


def particular_solution(
    model: LinearModel, speed_m_s, omega_rad_s, harmonics: Harmonics
) -> tuple[np.ndarray, np.ndarray]:
    """Complex particular solution per harmonic (Sec 3.1.2.2.1, Eq 3.10-3.15), batched.

    Parameters
    ----------
    model
        Linear model (Eq 3.1).
    speed_m_s, omega_rad_s
        Forward speed and cadence, broadcast against each other (e.g. ``v[:, None]`` and
        ``w[None, :]`` for a grid).
    harmonics
        Pedalling torque harmonics (``disturbance.torque_harmonics``).

    Returns
    -------
    roll, steer
        Complex amplitudes, shape ``broadcast(speed, omega) + (k,)``: the response to harmonic
        ``n_k`` is ``Re(roll[..., k] exp(i n_k w t))``. The amplitude at the cadence is
        ``abs(roll[..., 0])`` when ``n[0] == 1``; the phase is ``angle(...)``.
    """
    n, coef = harmonic_coefficients(harmonics)
    v, w = np.broadcast_arrays(np.asarray(speed_m_s, float), np.asarray(omega_rad_s, float))
    freq = w[..., None] * n  # (..., k)
    a = dynamic_stiffness(model, v[..., None], freq)  # (..., k, 2, 2)
    rhs = coef * (freq**2)[..., None]  # (..., k, 2)
    q = solve_2x2(a, rhs)
    # zero forcing (w = 0) gives zero response, also where the matrix is singular
    q = np.where((freq == 0)[..., None], 0.0, q)
    return q[..., 0], q[..., 1]


def solve_2x2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Batched solution of ``a x = b`` for 2 x 2 systems, ``a`` (..., 2, 2), ``b`` (..., 2).

    Cramer's rule, exact for 2 x 2 and fully vectorised (the same result as
    ``np.linalg.solve(a, b[..., None])[..., 0]``, checked in the tests, without LAPACK's
    per-matrix call overhead). A singular matrix gives inf/NaN entries, never an exception.
    """
    a11, a12, a21, a22 = a[..., 0, 0], a[..., 0, 1], a[..., 1, 0], a[..., 1, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_det = 1.0 / (a11 * a22 - a12 * a21)
        x0 = (a22 * b[..., 0] - a12 * b[..., 1]) * inv_det
        x1 = (a11 * b[..., 1] - a21 * b[..., 0]) * inv_det
    return np.stack([x0, x1], axis=-1)


def particular_solution_loop(model: LinearModel, speed_m_s: np.ndarray, omega_rad_s: np.ndarray,
                             harmonics: Harmonics) -> tuple[np.ndarray, np.ndarray]:
    """Reference per-point Python loop of :func:`particular_solution` (for tests and bench)."""
    n, coef = harmonic_coefficients(harmonics)
    roll = np.zeros((len(speed_m_s), len(omega_rad_s), len(n)), complex)
    steer = np.zeros_like(roll)
    for i, v in enumerate(speed_m_s):
        for j, w in enumerate(omega_rad_s):
            for k, nk in enumerate(n):
                f = nk * w
                if f == 0:
                    continue
                a = -(f**2) * model.M + 1j * f * v * model.C1 + model.g * model.K0 + v**2 * model.K2
                q = np.linalg.solve(a, coef[k] * f**2)
                roll[i, j, k], steer[i, j, k] = q
    return roll, steer


def superposed_amplitude(q: np.ndarray, n: np.ndarray, samples: int = 256) -> np.ndarray:
    """Peak amplitude ``max_t |Re sum_k q_k exp(i n_k w t)|`` of a multi-harmonic response.

    Evaluated on ``samples`` points of one cadence period (odd harmonics only: the signal is
    half-wave antisymmetric, so ``max |x|`` is the amplitude).
    """
    theta = np.linspace(0.0, 2 * np.pi, samples, endpoint=False)
    phase = np.exp(1j * np.asarray(n)[:, None] * theta[None, :])  # (k, s)
    x = np.real(np.einsum("...k,ks->...s", q, phase))
    return np.abs(x).max(axis=-1)


# --------------------------------------------------------------------------------------------
# Time solutions: analytic (LA) and numerical (LN)
# --------------------------------------------------------------------------------------------

@dataclass
class TimeSolution:
    """Time solutions on a speed x cadence grid (one method, one model).

    ``roll``/``steer`` are sampled at ``t_s``; NaN after a fall (``|roll|`` >= the fall angle).
    """

    speed_m_s: np.ndarray  # (n_v,)
    omega_rad_s: np.ndarray  # (n_w,)
    t_s: np.ndarray  # (n_t,)
    roll_rad: np.ndarray  # (n_v, n_w, n_t)
    steer_rad: np.ndarray
    t_end_s: np.ndarray  # (n_v, n_w)
    fell: np.ndarray  # (n_v, n_w) bool


def _truncate_at_fall(roll: np.ndarray, steer: np.ndarray, t: np.ndarray, fall_roll_rad: float):
    bad = ~np.isfinite(roll) | (np.abs(roll) >= fall_roll_rad) | ~np.isfinite(steer)
    fell = bad.any(axis=-1)
    first = np.where(fell, bad.argmax(axis=-1), len(t))
    mask = np.arange(len(t)) >= first[..., None]
    roll = np.where(mask, np.nan, roll)
    steer = np.where(mask, np.nan, steer)
    t_end = np.where(fell, t[np.maximum(first - 1, 0)], t[-1])
    return roll, steer, t_end, fell


def analytic_time_solution(
    model: LinearModel,
    speed_m_s: np.ndarray,
    omega_rad_s: np.ndarray,
    harmonics: Harmonics,
    t_s: np.ndarray,
    fall_roll_rad: float = np.pi / 2,
) -> TimeSolution:
    """Exact time solution, particular + homogeneous, zero initial state (Eq 3.9, 3.16-3.18).

    The homogeneous part ``x_h(t) = sum_i c_i xi_i exp(lambda_i t)`` uses the eigenvalues and
    eigenvectors of the state matrix at each speed; ``c`` solves ``x_p(0) + x_h(0) = 0``. This
    is Eq 3.16-3.17 written with complex exponentials (the real form there is the same sum).
    Vectorised over cadences and time; one small loop over speeds bounds the memory.

    Parameters
    ----------
    speed_m_s, omega_rad_s
        1-D grids.
    t_s
        Sample times, starting at 0.
    fall_roll_rad
        The record of a run ends where ``|roll|`` first reaches this (the bicycle fell).
    """
    v_grid = np.asarray(speed_m_s, float)
    w_grid = np.asarray(omega_rad_s, float)
    t = np.asarray(t_s, float)
    n, _ = harmonic_coefficients(harmonics)
    roll_out = np.empty((len(v_grid), len(w_grid), len(t)))
    steer_out = np.empty_like(roll_out)
    lam_all, vec_all = np.linalg.eig(state_matrix(model, v_grid))  # (n_v, 4), (n_v, 4, 4)
    # forcing phases exp(i n w t) do not depend on speed: cos/sin once for the whole grid
    arg = (w_grid[:, None, None] * n[None, :, None]) * t[None, None, :]  # (n_w, k, n_t)
    cos_p, sin_p = np.cos(arg), np.sin(arg)
    del arg
    freq = w_grid[:, None] * n[None, :]  # (n_w, k)
    for i, v in enumerate(v_grid):
        rq, sq = particular_solution(model, v, w_grid, harmonics)  # (n_w, k)
        q = np.stack([rq, sq], axis=-2)  # (n_w, 2, k)
        x0 = np.concatenate([q.sum(-1).real, (1j * freq[:, None, :] * q).sum(-1).real], axis=-1)
        lam, vec = lam_all[i], vec_all[i]
        c = np.linalg.solve(vec, -x0.T).T  # (n_w, 4)
        # cap the growth: a run has fallen long before exp(700); keeps 0 * growth = 0
        expo = np.multiply.outer(lam, t)
        hom = np.exp(np.minimum(expo.real, 700.0) + 1j * expo.imag)  # (4, n_t)
        with np.errstate(over="ignore", invalid="ignore"):
            qh = ((c[:, None, :] * vec[None, 0:2, :]) @ hom).real  # (n_w, 2, n_t)
            qp = q.real @ cos_p - q.imag @ sin_p  # Re(q exp(i n w t)), (n_w, 2, n_t)
            x = qh + qp
        roll_out[i], steer_out[i] = x[:, 0], x[:, 1]
    roll_out, steer_out, t_end, fell = _truncate_at_fall(roll_out, steer_out, t, fall_roll_rad)
    return TimeSolution(v_grid, w_grid, t, roll_out, steer_out, t_end, fell)


def numerical_time_solution(
    model: LinearModel,
    speed_m_s: float,
    omega_rad_s: float,
    harmonics: Harmonics,
    t_s: np.ndarray,
    *,
    rtol: float = 1e-3,
    atol: float = 1e-6,
    fall_roll_rad: float = np.pi / 2,
    method: str = "RK45",
    compiled: bool = True,
) -> tuple[np.ndarray, np.ndarray, float, bool]:
    """Numerical integration of the linear model from rest (LN; Sec 3.1.2.1, ode45 check).

    Dormand-Prince 5(4) (Matlab's ode45, scipy's RK45) with a terminal event at
    ``|roll| = fall_roll_rad``; what was simulated before the fall is kept. The run goes
    through :func:`pedalrepro.integrator.integrate`: compiled (``variant="scipy"``, solve_ivp's
    RK45 step for step, its quartic dense output and event location) unless ``compiled`` is
    False or ``method`` is not RK45 (then ``scipy.integrate.solve_ivp`` itself).

    Returns
    -------
    roll, steer, t_end_s, fell
        Samples at ``t_s`` (NaN after the fall), the last simulated time and the fall flag.
    """
    n, coef = harmonic_coefficients(harmonics)
    system = LinearSystem.bicycle(state_matrix(model, speed_m_s), model.M, n, coef, omega_rad_s)
    try:
        sim = integrate(system, np.zeros(4), t_s, rtol=rtol, atol=atol,
                        fall_roll_rad=fall_roll_rad, method=method, compiled=compiled,
                        variant="scipy")
    except SimulationError as err:
        raise RuntimeError(f"integration failed at v={speed_m_s}, w={omega_rad_s}: {err}") from err
    return sim.roll_rad, sim.steer_rad, sim.t_end_s, sim.fell


def numerical_time_solutions(
    model: LinearModel, speed_m_s: np.ndarray, omega_rad_s: np.ndarray, harmonics: Harmonics,
    t_s: np.ndarray, **kwargs,
) -> TimeSolution:
    """:func:`numerical_time_solution` on every grid point (a simulation sweep: one run each)."""
    v_grid = np.asarray(speed_m_s, float)
    w_grid = np.asarray(omega_rad_s, float)
    t = np.asarray(t_s, float)
    roll = np.empty((len(v_grid), len(w_grid), len(t)))
    steer = np.empty_like(roll)
    t_end = np.empty((len(v_grid), len(w_grid)))
    fell = np.zeros((len(v_grid), len(w_grid)), bool)
    for i, v in enumerate(v_grid):
        for j, w in enumerate(w_grid):
            roll[i, j], steer[i, j], t_end[i, j], fell[i, j] = numerical_time_solution(
                model, v, w, harmonics, t, **kwargs)
    return TimeSolution(v_grid, w_grid, t, roll, steer, t_end, fell)


def cadence_amplitudes(sol: TimeSolution, sample_rate_hz: float, window: str | None = "hann",
                       min_samples: int = 2, chunk: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """Hann-windowed DFT amplitude at the cadence of each time solution (Sec 3.1.2.1.1).

    Each run is analysed over what was simulated (up to its fall). Runs at zero cadence have
    zero forcing and get amplitude 0.

    Returns
    -------
    roll_amp_rad, steer_amp_rad
        Shape (n_v, n_w).
    """
    n_v, n_w = sol.t_end_s.shape
    n_t = sol.roll_rad.shape[-1]
    roll_amp = np.zeros((n_v, n_w))
    steer_amp = np.zeros((n_v, n_w))
    # the DFT kernel at each cadence, exp(-i w k / f_s), once for the grid (Eq 3.2 at f = w/2pi)
    arg = np.multiply.outer(sol.omega_rad_s, np.arange(n_t) / sample_rate_hz)
    cos_k, sin_k = np.cos(arg), np.sin(arg)
    del arg
    col = np.broadcast_to(np.arange(n_w)[None, :], (n_v, n_w))
    n_valid = np.isfinite(sol.roll_rad).sum(axis=-1)
    for length in np.unique(n_valid):  # runs of equal record length share one window
        sel = n_valid == length
        if length < min_samples:
            roll_amp[sel] = np.nan
            steer_amp[sel] = np.nan
            continue
        h = spectral.window(int(length), window)
        idx = col[sel]
        for name, out in (("roll_rad", roll_amp), ("steer_rad", steer_amp)):
            x = getattr(sol, name)[sel, :length] * h
            res = np.empty(len(idx))
            for lo in range(0, len(idx), chunk):  # bounded memory
                j = idx[lo:lo + chunk]
                xs = x[lo:lo + chunk]
                re = np.einsum("mn,mn->m", xs, cos_k[j, :length])
                im = np.einsum("mn,mn->m", xs, sin_k[j, :length])
                res[lo:lo + chunk] = 2.0 * np.hypot(re, im) / h.sum()
            out[sel] = res
    zero = sol.omega_rad_s == 0
    roll_amp[:, zero] = 0.0
    steer_amp[:, zero] = 0.0
    return roll_amp, steer_amp


def grid(step: float, maximum: float) -> np.ndarray:
    """``0:step:maximum`` as in Matlab (the end point included when it falls on the grid)."""
    count = int(np.floor(maximum / step + 1e-9)) + 1
    return np.arange(count) * step


# --------------------------------------------------------------------------------------------
# Grids, sampling and forcing (arguments: config section ``linear``, passed by the rules as params)
# --------------------------------------------------------------------------------------------

def speed_cadence_grid(speed_step_m_s: float, speed_max_m_s: float, omega_step_rad_s: float,
                       omega_max_rad_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Speeds (m/s) and cadences (rad/s) ``0:step:max`` of the particular-solution grid
    (Sec 3.1.2.2.1; config ``linear.ps_*``) or the time-solution grid (Sec 3.1.2.1;
    ``linear.time_*``)."""
    return grid(speed_step_m_s, speed_max_m_s), grid(omega_step_rad_s, omega_max_rad_s)


def time_samples(duration_s: float, sample_rate_hz: float) -> np.ndarray:
    """Sample times ``0 .. duration_s`` at ``sample_rate_hz`` (config ``linear.duration_s``,
    ``linear.sample_rate_hz``)."""
    dt = 1.0 / sample_rate_hz
    return np.arange(int(round(duration_s / dt)) + 1) * dt


def forcing(model: str, harmonics: Sequence[int] | None = None):
    """Pedalling torque harmonics (Eq 3.14) acting on a model (its bicycle's legs).

    ``harmonics``: the multiples of the cadence kept (config ``linear.harmonics``; default
    ``(1, 3, 5)``, the thesis's T(w, 3w, 5w)).
    """
    from . import disturbance
    from .linear import bicycle_of

    if harmonics is None:
        harmonics = (1, 3, 5)
    return disturbance.torque_harmonics(bicycle_of(model), harmonics=tuple(harmonics))
