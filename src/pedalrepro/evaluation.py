"""Evaluation of model simplifications, solution methods and parameters (Sec 3.1.3, 3.2.4-3.2.5).

Relative difference of cadence amplitudes (Eq 3.26)::

    RD_{1->2} = | (|phi_1| - |phi_2|) / |phi_1| | * 100 %

with case 1 the reference. The evaluation points this module computes need only linear
methods (the others, 1a and 1b, need the non-linear models)::

    ====  =====================================================  ===========  ==============
    point what                                                   reference 1  case 2
    ====  =====================================================  ===========  ==============
    1c    neglect speed and gravity                              PS           CAM
    2b    drop the 3w and 5w harmonics                           LA T(w,3w,5w)  LA T(w)
    3a    numerical vs analytic time solution                    LA           LN
    3b    DFT of the time solution vs particular solution        PS           LA (Hann DFT)
    4     cycling condition vs the reference 60 rpm, 5 m/s        PS(ref)      PS(v, w)
    5     posture: rigid rider for hands on the bars             HS / CF      HR / CR
    6     bicycle design: city vs hybrid                         HR           CR
    ====  =====================================================  ===========  ==============

Six numbered example points (Fig 3.10-3.29) lie on one gear-ratio line, GR ~ 2.3 (Sec 3.2.1).
The thesis does not list them; this project reads them as six equally spaced points of the
time-solution grid diagonal ``v = 0.8 w`` (``v = 0:0.4:10`` and ``w = 0:0.5:4 pi`` advance
together): GR = 0.8 / r_R = 2.36 (Stratos) and 2.35 (Browser), i.e. "~2.3". Every third
diagonal point from the 8th, ``(v, w) = (3.2, 4), (4.4, 5.5), (5.6, 7), (6.8, 8.5), (8, 10),
(9.2, 11.5)``, matches the text of Sec 3.2.1: point 1 falls quickly (large positive weave real
part); point 3 of model HS (5.6 m/s) shows the slowly growing weave with a period of about 3 s
(Im = 1.99 rad/s; the thesis: "around 1/3 Hz"); points 5 and 6 of HR and CR lie above the
capsize speed, where falling takes long; points 2-6 of CF lie above the speed where its weave
branch stabilises, where only the capsize root is unstable and the periodic part shows. Other
spacings along the diagonal fit the text less well (with every fourth point from the 4th, HS
point 3 would have Im = 1.77 rad/s, a 3.6 s period).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from . import gears, linear, response
from .relative_difference import relative_difference  # Eq 3.26 (a leaf module)

if TYPE_CHECKING:
    from .params import LinearModel

__all__ = [
    "LINEAR_POINTS", "MODEL_PAIRS", "DIAGONAL_SPEED_STEP_M_S", "DIAGONAL_OMEGA_STEP_RAD_S",
    "ExamplePoints", "example_points", "series_speed", "stable_speed_mask", "RDStats", "rd_stats",
    "reference_indices", "NONLINEAR_RD_MAPS", "nonlinear_rd_maps", "nonlinear_rd_stats",
]

#: The evaluation points of Sec 3.1.3 computed from linear methods only.
LINEAR_POINTS: tuple[str, ...] = ("1c", "2b", "3a", "3b", "4", "5", "6")
#: Comparisons of evaluation points 5 and 6: (reference model, compared model).
MODEL_PAIRS: dict[str, tuple[tuple[str, str], ...]] = {
    "5": (("HS", "HR"), ("CF", "CR")),
    "6": (("HR", "CR"),),
}
#: Diagonal step of the time grid and the indices of the six example points.
DIAGONAL_SPEED_STEP_M_S = 0.4
DIAGONAL_OMEGA_STEP_RAD_S = 0.5
_EXAMPLE_INDICES = (8, 11, 14, 17, 20, 23)


@dataclass(frozen=True)
class ExamplePoints:
    """The six numbered speed-cadence points of Fig 3.10-3.29 for one model."""

    speed_m_s: np.ndarray
    omega_rad_s: np.ndarray
    gear_ratio: float
    series_speed_m_s: float
    series_omega_rad_s: np.ndarray

    @property
    def labels(self) -> list[str]:
        return [str(i + 1) for i in range(len(self.speed_m_s))]


def example_points(model: str) -> ExamplePoints:
    """The six numbered points on the GR ~ 2.3 line (Fig 3.10-3.17, 3.20-3.27).

    Also the one-speed series of Fig 3.18, 3.19, 3.28, 3.29: the six cadences in decreasing
    order (Sec 3.2.2: "the cadence frequency peak shifts to lower frequencies" as the number
    grows) at :func:`series_speed` (just below the model's self-stable range, where the thesis
    sees the weave: "for a small forward speed range, just below the self-stable range"). See
    the module docstring for this reading.

    Parameters
    ----------
    model
        ``"benchmark"``, ``"HS"``, ``"CF"``, ``"HR"`` or ``"CR"`` (sets the wheel radius of GR).
    """
    idx = np.asarray(_EXAMPLE_INDICES, float)
    v = idx * DIAGONAL_SPEED_STEP_M_S
    w = idx * DIAGONAL_OMEGA_STEP_RAD_S
    gr = float(DIAGONAL_SPEED_STEP_M_S / DIAGONAL_OMEGA_STEP_RAD_S
               / gears.wheel_radius_m(linear.bicycle_of(model)))
    return ExamplePoints(v, w, gr, series_speed(model, v), w[::-1].copy())


def series_speed(model: str, speeds_m_s: np.ndarray) -> float:
    """Speed of the one-speed series (Fig 3.18, 3.19, 3.28, 3.29): the fastest of the numbered
    example points (``speeds_m_s``) below the start of the model's first self-stable range, from
    its eigenvalues (Sec 3.2.2: the weave shows "for a small forward speed range, just below the
    self-stable range ... a low positive real part of the oscillatory weave"); point 3 for a model
    with no self-stable range (CF) or none below it.

    HS: stable from 6.02 m/s -> 5.6 m/s, point 3, as the thesis's Fig 3.18; CR: from 5.05 m/s ->
    4.4 m/s (point 3's 5.6 m/s lies inside CR's self-stable range, where the weave is damped).
    """
    grid = np.arange(0.0, 15.0, 0.01)
    ranges = linear.stable_ranges(linear.linear_model(model), grid)
    below = speeds_m_s[speeds_m_s < ranges[0][0]] if ranges else speeds_m_s[:0]
    return float(below.max()) if below.size else float(speeds_m_s[2])


def stable_speed_mask(model_name: str, speed_m_s: np.ndarray,
                      eigen_step_m_s: float = 0.01) -> np.ndarray:
    """Speeds inside a self-stable range of the model (all eigenvalue real parts < 0)."""
    model = linear.linear_model(model_name)
    v = np.asarray(speed_m_s, float)
    grid = np.arange(0.0, max(v.max(), 0.0) + 2 * eigen_step_m_s, eigen_step_m_s)
    ranges = linear.stable_ranges(model, grid)
    mask = np.zeros(v.shape, bool)
    for lo, hi in ranges:
        mask |= (v > lo) & (v < hi)
    return mask


@dataclass
class RDStats:
    """Median and range of an RD map over a region (percent); ``count`` points used."""

    median: float
    minimum: float
    maximum: float
    count: int


def rd_stats(rd: np.ndarray, mask: np.ndarray) -> RDStats | None:
    """Median and range of ``rd`` where ``mask`` (and RD defined); ``None`` if nothing left."""
    values = np.asarray(rd)[np.asarray(mask) & np.isfinite(rd)]
    if values.size == 0:
        return None
    return RDStats(float(np.median(values)), float(values.min()), float(values.max()),
                   int(values.size))


def reference_indices(speed_m_s: np.ndarray, omega_rad_s: np.ndarray, speed_ref_m_s: float,
                      omega_ref_rad_s: float) -> tuple[int, int]:
    """Grid indices of the reference condition (evaluation point 4); exact grid point required."""
    i = int(np.argmin(np.abs(speed_m_s - speed_ref_m_s)))
    j = int(np.argmin(np.abs(omega_rad_s - omega_ref_rad_s)))
    return i, j


#: Non-linear evaluation points (Sec 3.1.3.1) and the RD map each is summarised from:
#: 1a (= 2a) NT vs NP, NP the reference; 1b LN vs NT, NT the reference; PS vs NP (Fig 3.34).
NONLINEAR_RD_MAPS: dict[str, str] = {"1a": "nt_np", "1b": "ln_nt", "ps_np": "ps_np"}


def nonlinear_rd_maps(
    models: dict[str, LinearModel],
    nt: dict[str, dict[str, np.ndarray]],
    np_: dict[str, dict[str, np.ndarray]],
    harmonics: dict[str, response.Harmonics],
    speed_m_s: np.ndarray,
    omega_rad_s: np.ndarray,
    t_s: np.ndarray,
    sample_rate_hz: float,
    fall_roll_rad: float,
) -> tuple[dict[str, np.ndarray], dict[str, list[tuple[float, float]]]]:
    """RD maps (Eq 3.26) of the non-linear evaluation points and each model's stable speeds.

    The linear references (PS, LN) come from the project's own linearisation of the same
    non-linear model (``models``), so that the RDs measure the method, not a parameter
    difference (Sec 3.2.4, Fig 3.34).

    Parameters
    ----------
    models
        Linearisation of each non-linear model, by name (HS, CF, HR, CR).
    nt, np_
        The NT and NP time-solution grids of each model (``roll_amp_rad``, ``steer_amp_rad``,
        shape ``(n_v, n_w)``, on ``speed_m_s`` x ``omega_rad_s``).
    harmonics
        Pedalling torque harmonics (Eq 3.14) of each model.
    speed_m_s, omega_rad_s, t_s
        The time-solution grid and sample times (s) of the NT/NP runs.
    sample_rate_hz, fall_roll_rad
        Sampling of the Hann DFT and the fall criterion of the LN runs.

    Returns
    -------
    maps
        ``speed_m_s``, ``omega_rad_s``, ``models`` and, per model and dof (roll, steer),
        ``<model>_<dof>_ps_np`` (RD of PS vs NP), ``<model>_<dof>_nt_np`` (NT vs NP),
        ``<model>_<dof>_ln_nt`` (LN vs NT), in percent, and ``<model>_stable`` (bool, ``(n_v,)``:
        speeds inside a self-stable range of the linearisation).
    stable_ranges
        The self-stable speed ranges (m/s) of each model's linearisation.
    """
    v, w = np.asarray(speed_m_s, float), np.asarray(omega_rad_s, float)
    maps: dict[str, np.ndarray] = {"speed_m_s": v, "omega_rad_s": w}
    ranges_of: dict[str, list[tuple[float, float]]] = {}
    for name, lm in models.items():
        h = harmonics[name]
        ln = response.analytic_time_solution(lm, v, w, h, t_s, fall_roll_rad)
        ln_roll, ln_steer = response.cadence_amplitudes(ln, sample_rate_hz, "hann")
        ps_roll, ps_steer = response.particular_solution(lm, v[:, None], w[None, :], h)
        ps_amp = {"roll": np.abs(ps_roll[..., 0]), "steer": np.abs(ps_steer[..., 0])}
        ln_amp = {"roll": ln_roll, "steer": ln_steer}
        ranges = linear.stable_ranges(lm, np.arange(0.0, v.max() + 0.02, 0.01))
        mask = np.zeros(v.shape, bool)
        for lo, hi in ranges:
            mask |= (v > lo) & (v < hi)
        for dof in ("roll", "steer"):
            nt_a, np_a = nt[name][f"{dof}_amp_rad"], np_[name][f"{dof}_amp_rad"]
            maps[f"{name}_{dof}_ps_np"] = relative_difference(np_a, ps_amp[dof])
            maps[f"{name}_{dof}_nt_np"] = relative_difference(np_a, nt_a)
            maps[f"{name}_{dof}_ln_nt"] = relative_difference(nt_a, ln_amp[dof])
        maps[f"{name}_stable"] = mask
        ranges_of[name] = ranges
    maps["models"] = np.array(list(models))
    return maps, ranges_of


def nonlinear_rd_stats(maps: dict[str, np.ndarray], point: str
                       ) -> dict[tuple[str, str], RDStats | None]:
    """Median and range of a non-linear evaluation point's RD map (:data:`NONLINEAR_RD_MAPS`)
    over the self-stable speeds of each model, by (model, dof), from :func:`nonlinear_rd_maps`."""
    key = NONLINEAR_RD_MAPS[point]
    v, w = maps["speed_m_s"], maps["omega_rad_s"]
    out: dict[tuple[str, str], RDStats | None] = {}
    for name in (str(m) for m in maps["models"]):
        mask = np.broadcast_to(np.asarray(maps[f"{name}_stable"], bool)[:, None], (v.size, w.size))
        for dof in ("roll", "steer"):
            out[(name, dof)] = rd_stats(maps[f"{name}_{dof}_{key}"], mask)
    return out
