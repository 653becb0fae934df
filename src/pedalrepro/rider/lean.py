"""A hands-free rider on the leaning-rider plant (beyond the thesis).

The plant is Moore's (2012, dissertation, chapter "Extensions of the Whipple Model") Whipple
bicycle with the rider's upper body ``G`` hinged to the rear frame by a lean joint, linearised
about upright straight running at constant speed, as BicycleParameters 1.5.2 generates it
(``bicycleparameters.models.MooreRiderLean2012Model``), with the Browser-with-Jason parameters
copied to ``data/parameters/mooreriderlean2012_browser_jason.yaml``. Of its 12 states the
ignorable ones (longitudinal position, wheel angles, rear-wheel rate) are dropped:

    x = [roll q4, steer q7, lean q9, roll' u4, steer' u7, lean' u9, heading q3, y_rear q2]

with inputs ``[T4 roll torque, T7 steer torque, T9 lean torque]`` (N m; T9 acts between the
upper body and the rear frame). Signs and the heading/lateral kinematics are those of
Meijaard et al. (2007) (checked in ``tests/rider/test_rider_lean.py``: locking the lean joint gives
the Whipple model of the Browser with a rigid Jason).

The hands-free rider (:func:`lean_plant`) is the loop structure of
:mod:`pedalrepro.rider.plant` with the lean torque ``T9`` as the output of the same
neuromuscular filter (30 rad/s, 0.707) and the innermost loop on the lean angle instead of the
steer angle: ``u = kDelta (lean_c - lean)``, ``lean_c = kPhiDot (phidot_c - roll')``, then the
roll, heading and lateral loops as before. The gain rules are those of
:mod:`pedalrepro.rider.gains`; :func:`inner_rule_scan` gives the numbers that decide whether
their first rule (the neuromuscular pair's damping 0.1289 with the lean loop closed) has a
usable solution.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from .. import params
from .gains import ZETA_DELTA
from .plant import (
    NEURO_DAMPING,
    NEURO_FREQ_RAD_S,
    Geometry,
    Plant,
    closed_matrix,
    control_law,
    neuromuscular_filter,
)

__all__ = [
    "DATA_FILES", "PARAMETER_FILE", "LEAN_STATES", "INPUTS", "PLANT_STATES", "DYNAMIC",
    "lean_parameters", "lean_state_space", "rigid_rider_state_space", "browser_geometry",
    "lean_plant", "InnerRuleScan", "inner_rule_scan", "rule_solution", "PHIDOT_GUESSES_S",
    "LEAN_TABLE_COLUMNS", "best_restoring_gain", "full_rules_from", "lean_rider_row",
    "lean_rider_table",
]

#: Read at run time (pedalrepro.dependencies: the rules' code inputs).
DATA_FILES: tuple[str, ...] = ("data/parameters/mooreriderlean2012_browser_jason.yaml",)
PARAMETER_FILE = "mooreriderlean2012_browser_jason"

#: States of :func:`lean_state_space` and their indices in BicycleParameters' 12 states
#: ``q1 q2 q3 q4 q6 q7 q8 q9 u4 u6 u7 u9``.
LEAN_STATES: tuple[str, ...] = ("roll", "steer", "lean", "roll_rate", "steer_rate", "lean_rate",
                                "heading", "y_rear")
_BP_KEEP: tuple[int, ...] = (3, 5, 7, 8, 10, 11, 2, 1)
_BP_DROP: tuple[int, ...] = (0, 4, 6, 9)
#: Inputs of :func:`lean_state_space` (N m).
INPUTS: tuple[str, ...] = ("T4_roll", "T7_steer", "T9_lean")
#: States of :func:`lean_plant`: the eight above, the filter's torque and its rate.
PLANT_STATES: tuple[str, ...] = (*LEAN_STATES, "torque", "torque_rate")
#: The states with dynamics of their own (heading and lateral position are pure integrators
#: while their loops are open).
DYNAMIC: tuple[int, ...] = (0, 1, 2, 3, 4, 5, 8, 9)


def lean_parameters() -> dict[str, float]:
    """Moore's leaning-rider parameters of the Browser with Jason (the module's data file)."""
    return params.benchmark_parameters(PARAMETER_FILE)


@cache
def _bp_model(items: tuple[tuple[str, float], ...]):
    # bicycleparameters' generated linearisation (slow to import: load it once)
    from bicycleparameters.models import MooreRiderLean2012Model
    from bicycleparameters.parameter_sets import MooreRiderLean2012ParameterSet

    return MooreRiderLean2012Model(MooreRiderLean2012ParameterSet({**dict(items), "v": 1.0}))


def lean_state_space(speed_m_s: float, parameters: dict[str, float] | None = None
                     ) -> tuple[np.ndarray, np.ndarray]:
    """``x' = A x + B T`` of the leaning-rider bicycle at one speed (module docstring).

    Parameters
    ----------
    speed_m_s
        Forward speed (m/s).
    parameters
        Moore's leaning-rider parameters; default :func:`lean_parameters`.

    Returns
    -------
    A, B
        (8, 8) over :data:`LEAN_STATES` and (8, 3) over :data:`INPUTS`.
    """
    par = lean_parameters() if parameters is None else dict(parameters)
    par.pop("v", None)
    a12, b12 = _bp_model(tuple(sorted(par.items()))).form_state_space_matrices(
        v=float(speed_m_s))
    keep, drop = list(_BP_KEEP), list(_BP_DROP)
    coupling = np.abs(a12[np.ix_(keep, drop)]).max()
    if coupling > 1e-9 * np.abs(a12).max():
        raise RuntimeError(f"leaning-rider model: the kept states depend on a dropped one "
                           f"({coupling:.3g}); BicycleParameters' state order changed?")
    return a12[np.ix_(keep, keep)], b12[keep]


def rigid_rider_state_space(speed_m_s: float, parameters: dict[str, float] | None = None
                            ) -> tuple[np.ndarray, np.ndarray]:
    """The leaning-rider model with the lean joint locked (lean = lean' = 0).

    The lean torque is the constraint torque that keeps ``lean'' = 0``; eliminating it gives
    the Whipple model of the bicycle with a rigid rider (rear frame = C + G).

    Returns
    -------
    A, B
        (4, 4) over ``[roll, steer, roll', steer']`` and (4, 2) over ``[T4, T7]``, the form of
        Eq 3.1 as a first-order system.
    """
    a, b = lean_state_space(speed_m_s, parameters)
    idx = [0, 1, 3, 4]
    row, bl = a[5], b[5]  # lean acceleration
    a_r = a[np.ix_(idx, idx)] - np.outer(b[idx, 2], row[idx]) / bl[2]
    b_r = b[np.ix_(idx, [0, 1])] - np.outer(b[idx, 2], bl[[0, 1]]) / bl[2]
    return a_r, b_r


def browser_geometry() -> Geometry:
    """Wheelbase, trail and steer-axis tilt of the Browser (``data/parameters/browser.yaml``)."""
    return Geometry.from_mapping(params.steer_geometry("city"))


def lean_plant(speed_m_s: float, parameters: dict[str, float] | None = None,
               geometry: Geometry | None = None,
               neuro_freq_rad_s: float = NEURO_FREQ_RAD_S,
               neuro_damping: float = NEURO_DAMPING) -> Plant:
    """The hands-free rider's plant: lean torque through the neuromuscular filter.

    Parameters
    ----------
    speed_m_s
        Forward speed (m/s).
    parameters
        Leaning-rider parameters (default :func:`lean_parameters`).
    geometry
        ``w``, ``c``, ``lam`` for the front-contact position ``yQ`` (default
        :func:`browser_geometry`).
    neuro_freq_rad_s, neuro_damping
        The filter (Hess et al. 2012: 30 rad/s, 0.707), output ``T9``.

    Returns
    -------
    Plant
        10 states (:data:`PLANT_STATES`), ``B_u`` into the filter, ``B_f`` the external roll
        and steer torques ``[T4, T7]`` (as the pedalling torques of Eq 3.1), ``C`` the loop
        outputs ``[lean, roll', roll, psi, yQ]``; ``control_input = "lean"``.
    """
    geo = browser_geometry() if geometry is None else geometry
    a8, b8 = lean_state_space(speed_m_s, parameters)
    n = len(PLANT_STATES)
    a = np.zeros((n, n))
    a[:8, :8] = a8
    a[:8, 8] = b8[:, 2]
    b_u = neuromuscular_filter(a, 8, neuro_freq_rad_s, neuro_damping)
    b_f = np.zeros((n, 2))
    b_f[:8] = b8[:, :2]
    c = np.zeros((5, n))
    c[0, 2] = 1.0  # lean angle (the steer angle's place)
    c[1, 3] = 1.0  # roll rate
    c[2, 0] = 1.0  # roll
    c[3, 6] = 1.0  # heading
    c[4, 7] = 1.0  # yQ = yP + w psi - c cos(lam) steer
    c[4, 6] = geo.w_m
    c[4, 1] = -geo.c_m * np.cos(geo.lam_rad)
    return Plant(a, b_u, b_f, c, float(speed_m_s), "lean")


@dataclass(frozen=True)
class InnerRuleScan:
    """The first gain rule on the lean input at one speed (:func:`inner_rule_scan`).

    Attributes
    ----------
    k_delta_n_m_rad
        Lean-angle gains scanned (N m/rad), ascending.
    nm_pair
        The neuromuscular pair (upper half plane), followed by continuity from the filter's
        own pole at zero gain.
    max_real_rad_s
        Largest real part of the closed inner loop (dynamic states) at each gain.
    least_damping
        Smallest damping ratio of any complex pair of the closed inner loop at each gain.
    """

    speed_m_s: float
    k_delta_n_m_rad: np.ndarray
    nm_pair: np.ndarray
    max_real_rad_s: np.ndarray
    least_damping: np.ndarray

    @property
    def nm_damping(self) -> np.ndarray:
        """Damping ratio of the neuromuscular pair at each gain."""
        return -self.nm_pair.real / np.abs(self.nm_pair)


def _inner_eigenvalues(p: Plant, k: float) -> np.ndarray:
    g = np.array([k, 0.0, 0.0, 0.0, 0.0])
    dyn = list(DYNAMIC)
    return np.linalg.eigvals(closed_matrix(p, g, 1)[np.ix_(dyn, dyn)])


def _inner_eigenvalues_at(p: Plant, gains: np.ndarray) -> np.ndarray:
    """:func:`_inner_eigenvalues` at every gain of ``gains``, (n, 8), in one batched solve: with
    the inner loop alone closed the feedback row of :func:`control_law` is the gain times its
    row at unit gain, so the closed matrices are :func:`closed_matrix`'s ``A + B_u k`` stacked
    (equal to the bit: ``1 x`` is exact) and their eigenvalues one stacked ``eigvals`` call."""
    dyn = list(DYNAMIC)
    unit, _ = control_law(p, np.array([1.0, 0.0, 0.0, 0.0, 0.0]), 1)
    k = np.asarray(gains, float)[:, None] * unit[None, :]
    mats = p.A[None, :, :] + p.B_u[None, :, None] * k[:, None, :]
    return np.linalg.eigvals(mats[:, dyn][:, :, dyn])


def _follow(p: Plant, gains: np.ndarray, start: complex) -> tuple[np.ndarray, ...]:
    pair = np.empty(len(gains), complex)
    max_re = np.empty(len(gains))
    least = np.empty(len(gains))
    near = start
    for i, lam in enumerate(_inner_eigenvalues_at(p, gains)):
        up = lam[lam.imag > 1e-9]
        near = pair[i] = up[np.argmin(np.abs(up - near))]
        max_re[i] = lam.real.max()
        least[i] = (-up.real / np.abs(up)).min()
    return pair, max_re, least


def inner_rule_scan(p: Plant, k_max_n_m_rad: float = 1e6, n: int = 1201) -> InnerRuleScan:
    """The neuromuscular pair and the inner loop's stability against the lean-angle gain.

    Gains ``+-geomspace(1e-2, k_max, n)`` and zero; the pair is followed outwards from zero
    gain, where it is the filter's own pole ``w_nm (-zeta_nm + i sqrt(1 - zeta_nm^2))``.
    """
    pos = np.geomspace(1e-2, k_max_n_m_rad, n)
    wn, z = -p.A[9, 8], -p.A[9, 9]
    wn = float(np.sqrt(wn))
    start = complex(-z / 2.0, wn * np.sqrt(1.0 - (z / (2.0 * wn)) ** 2))
    up = _follow(p, np.concatenate([[0.0], pos]), start)
    down = _follow(p, np.concatenate([[0.0], -pos]), start)
    k = np.concatenate([-pos[::-1], [0.0], pos])
    parts = [np.concatenate([d[1:][::-1], u]) for d, u in zip(down, up, strict=True)]
    return InnerRuleScan(float(p.speed_m_s), k, *parts)


def rule_solution(p: Plant, scan: InnerRuleScan, zeta: float = ZETA_DELTA) -> float:
    """The lean-angle gain (N m/rad) at which the followed neuromuscular pair of ``scan`` has
    damping ``zeta``: the crossing nearest zero gain, refined by ``brentq`` with the pair
    followed from the scanned one at the bracket's end; NaN if the pair never reaches it."""
    from scipy.optimize import brentq

    d = scan.nm_damping - zeta
    k = scan.k_delta_n_m_rad
    idx = np.nonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0]
    if idx.size == 0:
        return float("nan")
    i = int(idx[np.argmin(np.minimum(np.abs(k[idx]), np.abs(k[idx + 1])))])

    def f(kk: float) -> float:
        lam = _inner_eigenvalues(p, kk)
        up = lam[lam.imag > 1e-9]
        x = up[np.argmin(np.abs(up - scan.nm_pair[i]))]
        return float(-x.real / abs(x)) - zeta

    return float(brentq(f, k[i], k[i + 1], xtol=1e-10, rtol=1e-12))


#: Starting guesses of the roll-rate rule (s) continued from :func:`rule_solution`: that rule
#: has several solutions; every one reached from these is tried and the least unstable kept.
PHIDOT_GUESSES_S: tuple[float, ...] = (-1.0, -0.1, 0.1, 1.0, 10.0)
#: Columns of :func:`lean_rider_table` (units in the names; ``kPsi`` is rad/rad).
LEAN_TABLE_COLUMNS: tuple[str, ...] = (
    "speed_m_s", "open_loop_max_real_rad_s", "nm_damping_min_restoring",
    "nm_damping_max_restoring", "inner_max_real_min_restoring_rad_s",
    "inner_best_kDelta_n_m_rad", "rule_kDelta_n_m_rad", "rule_inner_max_real_rad_s",
    "rule_kPhiDot_s", "rule_kPhi_1_s", "rule_kPsi_rad_rad", "rule_kY_rad_m",
    "closed_loop_max_real_rad_s", "closed_loop_stable",
)


def best_restoring_gain(p: Plant, scan: InnerRuleScan) -> tuple[float, float]:
    """The restoring lean-angle gain (N m/rad) that minimises the closed inner loop's largest
    real part, and that real part (rad/s): the scan's best point refined by a bounded scalar
    minimisation between its neighbours (the minimum is a kink where two roots cross)."""
    from scipy.optimize import minimize_scalar

    k = scan.k_delta_n_m_rad
    i = int(np.argmin(np.where(k > 0, scan.max_real_rad_s, np.inf)))
    lo, hi = k[max(i - 1, 0)], k[min(i + 1, len(k) - 1)]
    res = minimize_scalar(lambda kk: float(_inner_eigenvalues(p, kk).real.max()),
                          bounds=(lo, hi), method="bounded", options={"xatol": 1e-8})
    if res.fun < scan.max_real_rad_s[i]:
        return float(res.x), float(res.fun)
    return float(k[i]), float(scan.max_real_rad_s[i])


def full_rules_from(p: Plant, k_delta_n_m_rad: float,
                    guesses_s: tuple[float, ...] = PHIDOT_GUESSES_S
                    ) -> tuple[np.ndarray, float]:
    """The remaining rules of :func:`pedalrepro.rider.gains.rule_gains` continued from the
    lean-angle gain ``k_delta_n_m_rad``: the gains (5,) whose fully closed loop has the
    smallest largest real part among the roll-rate solutions reached from ``guesses_s``, and
    that real part (rad/s); NaNs if none converges."""
    from .gains import rule_gains

    lam = _inner_eigenvalues(p, k_delta_n_m_rad)
    up = lam[lam.imag > 1e-9]
    w = float(np.abs(up[np.argmin(np.abs(-up.real / np.abs(up) - ZETA_DELTA))]))
    best, best_re = np.full(5, np.nan), float("nan")
    for g in guesses_s:
        try:
            res = rule_gains(p, guess=(k_delta_n_m_rad, w, g, w))
        except RuntimeError:
            continue
        re = float(np.linalg.eigvals(closed_matrix(p, res.gains)).real.max())
        if not re >= best_re:  # NaN-safe: the first, then any smaller
            best, best_re = res.gains, re
    return best, best_re


def lean_rider_row(speed_m_s: float) -> dict[str, float | bool]:
    """One row of :func:`lean_rider_table`: the gain rules on the lean-torque input."""
    p = lean_plant(speed_m_s)
    dyn = list(DYNAMIC)
    scan = inner_rule_scan(p)
    pos = scan.k_delta_n_m_rad > 0
    k_best, re_best = best_restoring_gain(p, scan)
    k_rule = rule_solution(p, scan)
    row: dict[str, float | bool] = {
        "speed_m_s": float(speed_m_s),
        "open_loop_max_real_rad_s": float(np.linalg.eigvals(p.A[np.ix_(dyn, dyn)]).real.max()),
        "nm_damping_min_restoring": float(scan.nm_damping[pos].min()),
        "nm_damping_max_restoring": float(scan.nm_damping[pos].max()),
        "inner_max_real_min_restoring_rad_s": re_best,
        "inner_best_kDelta_n_m_rad": k_best,
        "rule_kDelta_n_m_rad": k_rule,
    }
    if np.isfinite(k_rule):
        row["rule_inner_max_real_rad_s"] = float(_inner_eigenvalues(p, k_rule).real.max())
        g, re = full_rules_from(p, k_rule)
    else:
        row["rule_inner_max_real_rad_s"] = float("nan")
        g, re = np.full(5, np.nan), float("nan")
    row.update(zip(LEAN_TABLE_COLUMNS[8:12], map(float, g[1:]), strict=True))
    row["closed_loop_max_real_rad_s"] = re
    row["closed_loop_stable"] = bool(re < 0.0)
    return row


def lean_rider_table(speed_m_s: np.ndarray):
    """The hands-free lean-torque rider against speed (``results/tables/lean_rider.csv``).

    Per speed: the open plant's largest real part (the upper body falls about the free lean
    joint); the damping range of the neuromuscular pair over restoring lean gains
    (``kDelta > 0``) and the best the inner loop reaches there (its smallest largest real part
    and that gain); the first rule's solution (:func:`rule_solution`, N m/rad) with its inner
    loop's largest real part; the other gains continued from it (:func:`full_rules_from`) and
    the fully closed loop's largest real part.
    """
    import pandas as pd

    rows = [lean_rider_row(v) for v in np.asarray(speed_m_s, float)]
    return pd.DataFrame(rows, columns=list(LEAN_TABLE_COLUMNS))
