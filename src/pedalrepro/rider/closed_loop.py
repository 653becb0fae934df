"""The rider's closed loop around the thesis's linear models: gains against speed, closed-loop
eigenvalues, and the closed-loop pedalling response (beyond the thesis; Sec 3.1.2.2's
particular solution, Eq 3.10-3.15, with the rider's loops of :mod:`.plant` closed).

The pedalling torques ``f(t) = Re sum_k coef_k (n_k w)^2 exp(i n_k w t)`` (Eq 3.14) enter the
closed loop ``x' = A_cl(v) x + B_f f`` (the rider's command ``yc = 0``: straight running), so
the particular solution per harmonic is

    (i n w I - A_cl(v)) X_k = B_f coef_k (n_k w)^2,

solved for a whole speed x cadence grid in one batched complex solve (as ``response.PS``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import params, paths
from ..linear import benchmark_model, bicycle_of, linear_model
from ..params import LinearModel
from ..response import Harmonics, harmonic_coefficients
from .gains import DEFAULT_RULES, GainResult, RuleSettings, rule_gains
from .plant import N_STATES, Geometry, Plant, closed_matrix, plant

__all__ = [
    "DATA_FILES", "STEER_MODELS", "model_and_geometry", "GainSweep", "gain_sweep", "rule_gains_at",
    "published_gains", "closed_loop_matrices", "closed_loop_particular", "closed_loop_time",
]

#: Read at run time (pedalrepro.dependencies: the rules' code inputs).
DATA_FILES: tuple[str, ...] = ("data/published/humancontrol_gains.yaml",
                               "data/parameters/humancontrol_browser.yaml")

#: Models with steer-torque control (hands on the handlebars): the benchmark, the
#: HumanControl Browser-with-Jason plant, and the thesis's HS and CF.
STEER_MODELS: tuple[str, ...] = ("benchmark", "humancontrol_browser", "HS", "CF")


def model_and_geometry(name: str) -> tuple[LinearModel, Geometry]:
    """Linear model and bicycle geometry of ``name``.

    ``"benchmark"`` (Meijaard 2007), ``"HS"``, ``"CF"``, ``"HR"``, ``"CR"`` (Appendix B; the
    geometry of their bicycle, ``params.steer_geometry``), or the stem of a parameter file with
    benchmark parameters (e.g. ``"humancontrol_browser"``).
    """
    if name == "benchmark" or name in params.MODELS:
        return linear_model(name), Geometry.from_mapping(params.steer_geometry(bicycle_of(name)))
    try:
        p = params.benchmark_parameters(name)
    except FileNotFoundError as err:
        raise KeyError(f"unknown rider-control model {name!r}: expected benchmark, "
                       f"{params.MODELS} or a parameter file stem") from err
    return benchmark_model(name), Geometry.from_mapping(p)


@dataclass
class GainSweep:
    """Rule gains and closed-loop eigenvalues against speed for one model.

    ``gains`` (n_v, 5) is NaN where the rules did not converge (``failed`` holds why);
    ``eigenvalues`` (n_v, 8) of the fully closed loop; ``stable`` (n_v,) bool.
    """

    model: str
    speed_m_s: np.ndarray
    gains: np.ndarray
    omega_delta_rad_s: np.ndarray
    omega_phidot_rad_s: np.ndarray
    eigenvalues: np.ndarray
    stable: np.ndarray
    failed: dict[float, str]


def gain_sweep(name: str, speed_m_s: np.ndarray, settings: RuleSettings = DEFAULT_RULES,
               start_m_s: float = 5.0) -> GainSweep:
    """:func:`gains.rule_gains` for ``name`` at each speed, by continuation from ``start_m_s``.

    The inner-gain solve follows the damped pair from one speed to the next, going up and
    down from the grid speed nearest ``start_m_s`` (where ``compute_inner_gains``'s own guess
    holds for the benchmark). A speed where the rules fail gets NaN gains and its reason.
    """
    model, geo = model_and_geometry(name)
    v = np.asarray(speed_m_s, float)
    n = len(v)
    gains = np.full((n, 5), np.nan)
    wd = np.full(n, np.nan)
    wp = np.full(n, np.nan)
    eig = np.full((n, N_STATES), np.nan + 0j)
    failed: dict[float, str] = {}
    i0 = int(np.argmin(np.abs(v - start_m_s)))
    for order in (range(i0, n), range(i0 - 1, -1, -1)):
        guess = None
        for i in order:
            p = plant(model, geo, v[i])
            try:
                res = rule_gains(p, settings) if guess is None else rule_gains(p, settings, guess)
            except RuntimeError as err:
                failed[float(v[i])] = str(err)
                continue
            gains[i], wd[i], wp[i] = res.gains, res.omega_delta_rad_s, res.omega_phidot_rad_s
            guess = (res.gains[0], wd[i], res.gains[1], wp[i])
            eig[i] = np.linalg.eigvals(closed_matrix(p, res.gains))
    stable = np.isfinite(eig.real).all(axis=1) & (np.nan_to_num(eig.real, nan=1.0).max(axis=1)
                                                  < 0.0)
    return GainSweep(name, v, gains, wd, wp, eig, stable, failed)


def rule_gains_at(name: str, speed_m_s: float, settings: RuleSettings = DEFAULT_RULES
                  ) -> GainResult:
    """The rule gains of ``name`` at one speed, continued from 5 m/s (:func:`gain_sweep`)."""
    steps = max(2, int(np.ceil(abs(speed_m_s - 5.0) / 0.25)) + 1)
    sweep = gain_sweep(name, np.linspace(5.0, speed_m_s, steps), settings)
    i = int(np.argmin(np.abs(sweep.speed_m_s - speed_m_s)))
    if not np.isfinite(sweep.gains[i]).all():
        raise RuntimeError(sweep.failed.get(float(sweep.speed_m_s[i]), "rules failed"))
    return GainResult(sweep.gains[i], float(sweep.omega_delta_rad_s[i]),
                      float(sweep.omega_phidot_rad_s[i]))


def published_gains(table: str, speed_m_s: np.ndarray) -> np.ndarray:
    """A HumanControl gain table (``data/published/humancontrol_gains.yaml``), linearly
    interpolated in speed; NaN outside the tabulated speeds (n_v, 5).

    Used only where no rule applies: the roll-torque (hands-free stand-in) rider, whose
    inner-loop damping rule has no solution (the tables are comparison values elsewhere).
    """
    data = params.read_yaml(paths.PUBLISHED / "humancontrol_gains.yaml")
    if table not in data:
        raise KeyError(f"no gain table {table!r} in humancontrol_gains.yaml")
    rows = np.array(data[table], float)
    v = np.asarray(speed_m_s, float)
    out = np.column_stack([np.interp(v, rows[:, 0], rows[:, j], left=np.nan, right=np.nan)
                           for j in range(1, 6)])
    return out


def closed_loop_matrices(name: str, speed_m_s: np.ndarray, gains: np.ndarray,
                         control_input: str = "steer") -> tuple[np.ndarray, Plant]:
    """Closed-loop state matrices (n_v, 8, 8) at the speeds with the given gains (n_v, 5)."""
    model, geo = model_and_geometry(name)
    mats = np.empty((len(speed_m_s), N_STATES, N_STATES))
    p = None
    for i, v in enumerate(np.asarray(speed_m_s, float)):
        p = plant(model, geo, v, control_input=control_input)
        mats[i] = closed_matrix(p, gains[i])
    return mats, p


def closed_loop_particular(name: str, speed_m_s: np.ndarray, gains: np.ndarray,
                           omega_rad_s: np.ndarray, harmonics: Harmonics,
                           control_input: str = "steer") -> tuple[np.ndarray, np.ndarray]:
    """Closed-loop particular solution (module docstring) on a speed x cadence grid.

    Parameters
    ----------
    name
        Model name (:func:`model_and_geometry`).
    speed_m_s
        Speeds (n_v,).
    gains
        Rider gains at those speeds (n_v, 5); a row with NaN gives NaN responses.
    omega_rad_s
        Cadences (n_w,), rad/s.
    harmonics
        Pedalling torque harmonics (Eq 3.14).
    control_input
        ``"steer"`` (hands on) or ``"roll"`` (the hands-free stand-in), :func:`plant.plant`.

    Returns
    -------
    roll, steer
        Complex amplitudes (n_v, n_w, k) as ``response.particular_solution``.
    """
    n, coef = harmonic_coefficients(harmonics)
    a_cl, p = closed_loop_matrices(name, speed_m_s, np.asarray(gains, float), control_input)
    w = np.asarray(omega_rad_s, float)
    freq = w[:, None] * n[None, :]  # (n_w, k)
    eye = np.eye(N_STATES)
    lhs = 1j * freq[None, :, :, None, None] * eye - a_cl[:, None, None]  # (n_v, n_w, k, 8, 8)
    rhs = (p.B_f @ coef.T).T * 1.0  # (k, 8)
    rhs = rhs[None, None] * (freq**2)[None, :, :, None]
    bad = ~np.isfinite(lhs).all(axis=(-2, -1))
    lhs = np.where(bad[..., None, None], eye, lhs)
    x = np.linalg.solve(lhs, rhs[..., None])[..., 0]
    x = np.where(bad[..., None], np.nan, x)
    x = np.where((freq == 0)[None, :, :, None], 0.0, x)
    return x[..., 0], x[..., 1]


def closed_loop_time(name: str, speed_m_s: float, gains: np.ndarray, omega_rad_s: float,
                     harmonics: Harmonics, t_s: np.ndarray, control_input: str = "steer"
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Closed-loop time history from rest: particular + homogeneous solution (as LA, Eq 3.9,
    3.16-3.18, with the closed-loop state matrix), roll and steer (rad) at ``t_s``.

    ``x(t) = Re sum_k X_k exp(i n_k w t) + sum_i c_i xi_i exp(lambda_i t)`` with ``c`` such
    that ``x(0) = 0``; ``X_k`` from :func:`closed_loop_particular`.
    """
    n, coef = harmonic_coefficients(harmonics)
    a_cl, p = closed_loop_matrices(name, np.array([speed_m_s]), np.asarray(gains)[None],
                                   control_input)
    freq = omega_rad_s * n
    eye = np.eye(N_STATES)
    xk = np.stack([np.linalg.solve(1j * f * eye - a_cl[0], p.B_f @ c * f**2)
                   for f, c in zip(freq, coef, strict=True)])  # (k, 8)
    t = np.asarray(t_s, float)
    xp = np.real(np.exp(1j * np.outer(t, freq)) @ xk)  # (n_t, 8)
    lam, vec = np.linalg.eig(a_cl[0])
    c0 = np.linalg.solve(vec, -xp[0])
    expo = np.minimum(np.outer(t, lam).real, 700.0) + 1j * np.outer(t, lam).imag
    xh = np.real((np.exp(expo) * c0) @ vec.T)
    x = xp + xh
    return x[:, 0], x[:, 1]
