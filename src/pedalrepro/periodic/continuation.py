"""Continuation of periodic orbits in speed, cadence or torque scale (pseudo-arclength), the
multiplier crossings, and the branch rule's output (``rules/periodic.smk``)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .. import linear
from .solver import ConvergenceError, Orbit, OrbitSolver, own_linearisation

__all__ = ["Branch", "continue_branch", "write_branches"]


@dataclass
class Branch:
    """A continued branch of periodic orbits.

    ``parameter`` is ``"speed_m_s"`` or ``"omega_rad_s"``; arrays run along the branch (in
    arclength order, so a fold shows as a parameter that turns back). ``crossings``: where the
    number of Floquet multipliers outside the unit circle changes, with the parameter value
    (interpolated in ``log |mu|``) and the kind of crossing (``+1``, ``-1`` or ``complex``).
    """

    model: str
    method: str
    parameter: str
    fixed: float
    values: np.ndarray
    roll_amp_rad: np.ndarray
    steer_amp_rad: np.ndarray
    multipliers: np.ndarray
    residual: np.ndarray
    crossings: list[dict]

    @property
    def stable(self) -> np.ndarray:
        return np.max(np.abs(self.multipliers), axis=1) < 1.0

    def arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The branch as arrays (for ``np.savez``)."""
        c = self.crossings
        return {f"{prefix}values": self.values, f"{prefix}roll_amp_rad": self.roll_amp_rad,
                f"{prefix}steer_amp_rad": self.steer_amp_rad,
                f"{prefix}multipliers": self.multipliers, f"{prefix}residual": self.residual,
                f"{prefix}stable": self.stable,
                f"{prefix}crossing_values": np.array([x["value"] for x in c], float),
                f"{prefix}crossing_kinds": np.array([x["kind"] for x in c], dtype="U8")}


def _crossing_kind(mu: complex) -> str:
    ang = abs(float(np.angle(mu)))
    return "+1" if ang < 1e-3 else ("-1" if ang > np.pi - 1e-3 else "complex")


def _crossings(values: np.ndarray, mus: np.ndarray) -> list[dict]:
    out = []
    n_out = np.sum(np.abs(mus) > 1.0, axis=1)
    for i in range(len(values) - 1):
        if n_out[i] == n_out[i + 1]:
            continue
        # the multiplier nearest the unit circle after the change
        k = int(np.argmin(np.abs(np.log(np.abs(mus[i + 1])))))
        a = np.log(np.abs(mus[i])).copy()
        b = np.log(np.abs(mus[i + 1]))
        ka = int(np.argmin(np.abs(a)))
        frac = a[ka] / (a[ka] - b[k]) if a[ka] != b[k] else 0.5
        frac = min(max(frac, 0.0), 1.0)
        out.append({"value": float(values[i] + frac * (values[i + 1] - values[i])),
                    "kind": _crossing_kind(mus[i + 1][k]),
                    "unstable_after": int(n_out[i + 1])})
    return out


def _check_parameter(parameter: str, method: str, start: float, stop: float,
                     cadence_rad_s: float | None) -> None:
    """Reject a continuation that :func:`continue_branch` cannot run.

    Parameters
    ----------
    parameter, method, start, stop, cadence_rad_s
        As in :func:`continue_branch`.

    Raises
    ------
    ValueError
        For an unknown parameter, a cadence or torque-scale branch of another method than NT,
        or a torque-scale branch without a cadence or over non-positive scales.
    """
    if parameter not in ("speed_m_s", "omega_rad_s", "torque_scale"):
        raise ValueError(f"unknown continuation parameter {parameter!r}")
    if parameter in ("omega_rad_s", "torque_scale") and method != "NT":
        raise ValueError(f"continuation in {parameter} is available for NT (NP has no torques "
                         "and its legs depend on the cadence)")
    if parameter == "torque_scale":
        if cadence_rad_s is None:
            raise ValueError("continuation in torque_scale needs cadence_rad_s")
        if min(start, stop) <= 0.0:
            raise ValueError("a torque-scale branch runs over positive scales "
                             f"(got {start} .. {stop})")


def _solver_factory(model: str, method: str, parameter: str, fixed: float,
                    cadence_rad_s: float | None, kw: dict) -> Callable[[float], OrbitSolver]:
    """The orbit solver at a parameter value along the branch.

    Parameters
    ----------
    model, method, parameter, fixed, cadence_rad_s
        As in :func:`continue_branch`.
    kw
        Keyword arguments of every :class:`OrbitSolver` (``torque_scale``, ``rtol``,
        ``max_growth``).

    Returns
    -------
    callable
        ``solver_at(p)``: in speed, one solver (made on the first call) set to the speed ``p``;
        in cadence or torque scale, a new solver at ``p`` set to the speed ``fixed``.
    """
    solvers: dict[float, OrbitSolver] = {}

    def solver_at(p: float) -> OrbitSolver:
        if parameter == "speed_m_s":
            s = solvers.get(0.0) or solvers.setdefault(0.0, OrbitSolver(model, method, fixed,
                                                                        **kw))
            s.set_speed(p)
            return s
        if parameter == "torque_scale":
            s = OrbitSolver(model, method, cadence_rad_s, **dict(kw, torque_scale=p))
        else:
            s = OrbitSolver(model, method, p, **kw)
        s.set_speed(fixed)
        return s

    return solver_at


def _segments(solver_at: Callable[[float], OrbitSolver], model: str, method: str,
              parameter: str, start: float, stop: float, fixed: float, kw: dict) -> int:
    """The number of shooting segments, the worst case over the range, fixed along the branch.

    Parameters
    ----------
    solver_at
        From :func:`_solver_factory`.
    model, method, parameter, start, stop, fixed
        As in :func:`continue_branch`.
    kw
        Keyword arguments of every :class:`OrbitSolver`.

    Returns
    -------
    int
        Segments: the most over 11 speeds of the range (speed), those at the fixed speed
        (torque scale) or those of the solver at the range's lower end (cadence).
    """
    lo, hi = sorted((start, stop))
    probe = np.linspace(lo, hi, 11)
    if parameter == "speed_m_s":
        s0 = solver_at(start)
        return max(s0.segments_for(p) for p in probe)
    if parameter == "torque_scale":
        return solver_at(start).segments_for(fixed)
    return max(OrbitSolver(model, method, max(p, 1e-3), **kw).segments_for(fixed)
               for p in probe[:1])


def _first_points(solver_at: Callable[[float], OrbitSolver], parameter: str, start: float,
                  stop: float, fixed: float, ds: float, m: int) -> list[tuple[float, Orbit]]:
    """The branch's first two orbits, solved directly, whose secant starts the continuation.

    Parameters
    ----------
    solver_at
        From :func:`_solver_factory`.
    parameter, start, stop, fixed, ds
        As in :func:`continue_branch`.
    m
        Shooting segments (:func:`_segments`).

    Returns
    -------
    list of (float, Orbit)
        The orbits at ``start`` (on ``m`` segments) and one step ``ds`` (at most the range)
        towards ``stop`` (started from the first).

    Raises
    ------
    ConvergenceError
        If either orbit does not converge.
    """
    s = solver_at(start)
    o0 = s.solve(start if parameter == "speed_m_s" else fixed, segments=m)
    if not o0.converged:
        raise ConvergenceError(f"no orbit at the branch start {parameter} = {start}",
                               o0.periodicity_residual)
    direction = 1.0 if stop >= start else -1.0
    p1 = start + direction * min(ds, abs(stop - start))
    s = solver_at(p1)
    o1 = s.solve(p1 if parameter == "speed_m_s" else fixed, start=o0.nodes)
    if not o1.converged:
        raise ConvergenceError(f"no orbit at {parameter} = {p1}", o1.periodicity_residual)
    return [(start, o0), (p1, o1)]


def _correct(solver_at: Callable[[float], OrbitSolver], Xp: np.ndarray, t: np.ndarray, m: int,
             zs: float, tol: float) -> tuple[float, Orbit, np.ndarray] | None:
    """Pseudo-arclength corrector: Newton on ``R(z, p) = 0`` and ``t . (X - Xp) = 0``.

    Parameters
    ----------
    solver_at
        From :func:`_solver_factory`.
    Xp
        The predicted point (scaled nodes, then the parameter).
    t
        The unit secant, normal to the arclength constraint.
    m
        Shooting segments.
    zs
        The scale of the nodes in the unknowns.
    tol
        Periodicity residual to reach (relative to ``zs``).

    Returns
    -------
    tuple of (float, Orbit, numpy.ndarray) or None
        The parameter, the orbit and the corrected unknowns; ``None`` if eight Newton steps do
        not converge or a step fails (floating-point error, singular matrix).
    """
    Y = Xp.copy()
    for _ in range(8):
        nodes, p = Y[:-1].reshape(m, 4) * zs, float(Y[-1])
        try:
            s = solver_at(p)
            ev = s.residual(nodes)
            R = ev["R"].ravel()
            res = float(np.max(np.abs(R)))
            arc = float(t @ (Y - Xp))
            if res <= tol * zs + 1e-15 and abs(arc) <= 1e-10:
                return p, s._orbit(nodes, ev, res, True, 0, ev["n_rhs"]), Y
            dp = 1e-6 * max(1.0, abs(p))
            ev2 = solver_at(p + dp).residual(nodes, variational=False)
            s = solver_at(p)
        except (FloatingPointError, ZeroDivisionError):
            return None
        A = np.zeros((4 * m + 1, 4 * m + 1))
        A[:-1, :-1] = ev["J"] * zs
        A[:-1, -1] = (ev2["R"].ravel() - R) / dp
        A[-1] = t
        try:
            dY = np.linalg.solve(A, -np.concatenate([R, [arc]]))
        except np.linalg.LinAlgError:
            return None
        Y = Y + dY
    return None


def continue_branch(model: str, method: str, parameter: str, start: float, stop: float,
                    fixed: float, *, ds: float = 0.1, ds_min: float = 1e-3, ds_max: float = 0.5,
                    max_points: int = 400, torque_scale: float = 1.0, rtol: float = 1e-9,
                    max_growth: float = 100.0, tol: float = 1e-11,
                    refine: float | None = 1e-4, cadence_rad_s: float | None = None) -> Branch:
    """Follow a branch of periodic orbits from ``start`` to ``stop`` in ``parameter``.

    Secant predictor and pseudo-arclength corrector (Doedel et al. 2003; Keller's method):
    unknowns ``X = (z nodes / z_scale, p)``, equations ``R(z, p) = 0`` and
    ``t . (X - X_pred) = 0`` with ``t`` the unit secant; ``dR/dp`` by a forward difference. The
    step ``ds`` (in the scaled unknowns: m/s or rad/s for the parameter, orbit size for the
    nodes) grows after easy corrections and halves after failures. A fold in the parameter is
    passed (the arclength keeps increasing).

    Parameters
    ----------
    parameter
        ``"speed_m_s"`` (``fixed``: the cadence, rad/s), ``"omega_rad_s"`` (NT only;
        ``fixed``: the speed, m/s) or ``"torque_scale"`` (NT only: the factor on the pedalling
        torques, where folds appear at large torques near the weave resonance; ``fixed``: the
        speed, m/s, and ``cadence_rad_s`` the cadence). Start a torque-scale branch above 0 (the
        orbit of scale 0 is the trivial one, and the unknowns are scaled by the first orbit).
    refine
        Locate each multiplier crossing by bisection to this parameter tolerance (``None``:
        linear interpolation of ``log |mu|`` between branch points only).
    """
    _check_parameter(parameter, method, start, stop, cadence_rad_s)
    kw = dict(torque_scale=torque_scale, rtol=rtol, max_growth=max_growth)
    solver_at = _solver_factory(model, method, parameter, fixed, cadence_rad_s, kw)
    lo, hi = sorted((start, stop))
    m = _segments(solver_at, model, method, parameter, start, stop, fixed, kw)
    pts = _first_points(solver_at, parameter, start, stop, fixed, ds, m)
    (_, o0), (p1, o1) = pts
    direction = 1.0 if stop >= start else -1.0
    zs = max(float(np.max(np.abs(o0.nodes))), 1e-12)

    def pack(nodes, p):
        return np.concatenate([nodes.ravel() / zs, [p]])

    X0, X1 = pack(o0.nodes, start), pack(o1.nodes, p1)
    t = (X1 - X0) / np.linalg.norm(X1 - X0)
    X = X1
    h = ds
    while len(pts) < max_points:
        p_now = X[-1]
        if (p_now - stop) * direction >= 0 or not (min(lo, hi) - 1e-9 <= p_now <= max(lo, hi)
                                                    + 1e-9):
            break
        step = _correct(solver_at, X + h * t, t, m, zs, tol)
        if step is None:
            h /= 2
            if h < ds_min:
                break
            continue
        p, orb, Y = step
        pts.append((p, orb))
        t_new = (Y - X) / np.linalg.norm(Y - X)
        t = t_new
        X = Y
        h = min(h * 1.5, ds_max)
    return _branch(model, method, parameter, fixed, pts, solver_at, refine)


def _branch(model: str, method: str, parameter: str, fixed: float,
            pts: list[tuple[float, Orbit]], solver_at: Callable[[float], OrbitSolver],
            refine: float | None) -> Branch:
    """The :class:`Branch` of the continued points, with its multiplier crossings.

    Parameters
    ----------
    model, method, parameter, fixed, refine
        As in :func:`continue_branch`.
    pts
        ``(parameter value, orbit)`` along the branch.
    solver_at
        From :func:`_solver_factory` (for the bisection of the crossings).

    Returns
    -------
    Branch
    """
    values = np.array([p for p, _ in pts])
    orbs = [o for _, o in pts]
    mus = np.array([o.floquet_multipliers for o in orbs])
    crossings = _crossings(values, mus)
    if refine:
        for c in crossings:
            c["value"] = _refine_crossing(solver_at, parameter, fixed, pts, c, refine)
    return Branch(model, method, parameter, float(fixed), values,
                  np.array([o.roll_amplitude_rad for o in orbs]),
                  np.array([o.steer_amplitude_rad for o in orbs]), mus,
                  np.array([o.periodicity_residual for o in orbs]), crossings)


def _refine_crossing(solver_at, parameter, fixed, pts, crossing, tol) -> float:
    """Bisection on the parameter between the two branch points that bracket a crossing
    (where the count of multipliers outside the unit circle changes), to ``tol``."""
    values = [p for p, _ in pts]
    n_out = [int(np.sum(np.abs(o.floquet_multipliers) > 1.0)) for _, o in pts]
    i = next(k for k in range(len(pts) - 1) if n_out[k] != n_out[k + 1]
             and min(values[k], values[k + 1]) <= crossing["value"]
             <= max(values[k], values[k + 1]))
    (a, oa), (b, _) = pts[i], pts[i + 1]
    na = n_out[i]
    while abs(b - a) > tol:
        mid = 0.5 * (a + b)
        s = solver_at(mid)
        o = s.solve(mid if parameter == "speed_m_s" else fixed, start=oa.nodes)
        if not o.converged:
            break
        if int(np.sum(np.abs(o.floquet_multipliers) > 1.0)) == na:
            a, oa = mid, o
        else:
            b = mid
    return 0.5 * (a + b)



def write_branches(path, model: str, methods, cadence_rpm: float, speed_range_m_s,
                   torque_scales, *, ds: float, rtol: float, max_growth: float,
                   eigen_step_m_s: float = 0.01) -> list[Branch]:
    """Continuation in speed at one cadence for each method and torque scale, saved as
    ``.npz`` (keys ``<method>_<k>_<field>`` of :meth:`Branch.arrays`, ``torque_scales``,
    ``methods``) with the self-stable speed ranges of the model's own linearisation
    (``linear_stable_ranges_m_s``, n x 2)."""
    w = float(cadence_rpm) * 2.0 * np.pi / 60.0
    lo, hi = (float(x) for x in speed_range_m_s)
    arrays, branches = {}, []
    for method in methods:
        for k, scale in enumerate(torque_scales):
            if method == "NP" and scale != 1.0:
                continue
            br = continue_branch(model, method, "speed_m_s", lo, hi, w, ds=ds, rtol=rtol,
                                 max_growth=max_growth, torque_scale=float(scale))
            branches.append(br)
            arrays.update(br.arrays(f"{method}_{k}_"))
    lin = own_linearisation(model)
    ranges = linear.stable_ranges(lin, np.arange(0.0, hi + 2 * eigen_step_m_s, eigen_step_m_s))
    np.savez_compressed(path, model=model, omega_rad_s=w, cadence_rpm=float(cadence_rpm),
                        methods=np.array(list(methods)),
                        torque_scales=np.asarray(torque_scales, float),
                        linear_stable_ranges_m_s=np.array(ranges, float).reshape(-1, 2),
                        **arrays)
    return branches


