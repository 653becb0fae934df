"""Open loop against closed loop against measurement (beyond the thesis; Sec 4.2, Table 4.2).

One row per measured point and quantity (:data:`VALIDATION_COLUMNS`): the measured cadence
amplitude, the open-loop model (the particular solution of the Appendix B model, Eq 3.10-3.15,
as Table 4.1) and the closed-loop model (:mod:`pedalrepro.rider.closed_loop`) at the same speed
and cadence, and their relative differences ``RD = |measured - model| / measured * 100``
(Table 4.1 caption).

Measured sources (:func:`measured_points`):

- ``Table 4.1 (published)``: the thesis's printed measured HR and CR amplitudes (published
  comparison values, rounded to 3 decimals);
- ``run 3045``: the real public-subset run (HR, 25 km/h) as the mocap part measures it;
- ``CF spectra``: Moore's measured closed-loop spectra (:mod:`pedalrepro.mocap.spectra`), the
  nearest bin at the drawn cadence (the thesis's reading), labelled "measured (published
  spectra)".

The closed loop: hands on (HS, CF), the steer-torque rider with the rule gains
(:func:`.closed_loop.gain_sweep`); hands free (HR, CR), the roll-torque rider with
HumanControl's published benchmark roll gains (no rule applies: :func:`hands_free_gains`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from .. import linear, response
from . import closed_loop
from .plant import N_STATES, closed_matrix, plant

__all__ = [
    "VALIDATION_COLUMNS", "GAIN_COLUMNS", "TABLE_4_2_CLOSED_COLUMNS", "DYNAMIC", "HANDS_ON",
    "HANDS_FREE", "ROLL_TABLE", "SPECTRA_SOURCE", "TABLE_4_1_SOURCE", "rider_of",
    "hands_free_gains", "rider_gains", "measured_points", "model_amplitudes", "validation_table",
    "table_4_2_closed", "steer_stiffness_sweep", "TABLE_4_2_KEYS", "matching_stiffness",
]

VALIDATION_COLUMNS: tuple[str, ...] = (
    "system", "speed_kmh", "cadence_rpm", "source", "quantity", "measured_rad", "open_loop_rad",
    "closed_loop_rad", "rd_open_percent", "rd_closed_percent", "closed_loop_stable",
    "closed_loop_rider",
)
GAIN_COLUMNS: tuple[str, ...] = ("model", "speed_m_s", "kDelta", "kPhiDot", "kPhi", "kPsi", "kY",
                                 "source")
TABLE_4_2_CLOSED_COLUMNS: tuple[str, ...] = (
    "system", "source", "n_points", "roll_rd_open_median_percent", "roll_rd_open_range_percent",
    "roll_rd_closed_median_percent", "roll_rd_closed_range_percent",
    "steer_rd_open_median_percent", "steer_rd_open_range_percent",
    "steer_rd_closed_median_percent", "steer_rd_closed_range_percent",
)
#: States of the roll-steer dynamics and the filter (heading and lateral position are pure
#: integrators while their loops are open).
DYNAMIC = [0, 1, 2, 3, 6, 7]
HANDS_ON: tuple[str, ...] = ("HS", "CF")
HANDS_FREE: tuple[str, ...] = ("HR", "CR")
#: The gain table of the hands-free stand-in rider.
ROLL_TABLE = "BenchmarkRoll"
SPECTRA_SOURCE = "CF spectra (measured (published spectra))"
TABLE_4_1_SOURCE = "Table 4.1 (published)"


def rider_of(system: str) -> str:
    """``"steer (rule gains)"`` for hands on, ``"roll (published benchmark roll gains)"``."""
    if system in HANDS_ON:
        return "steer (rule gains)"
    if system in HANDS_FREE:
        return f"roll ({ROLL_TABLE} published gains)"
    raise KeyError(f"no rider for system {system!r}: expected {HANDS_ON + HANDS_FREE}")


def hands_free_gains(speed_m_s: np.ndarray) -> np.ndarray:
    """The roll-torque rider's gains: HumanControl's published ``BenchmarkRollGains.txt``,
    linearly interpolated (5-10 m/s; NaN outside).

    The rules do not carry over: with the roll-rate loop closed on the roll-torque input no
    closed-loop pair reaches the 0.0855 damping of the steer rule (the benchmark at 5 m/s: the
    lightly damped pair stays at 0.167-0.173 for kPhiDot 10-300), and ``generate_data.m``'s
    inner rule is written for the steer input only.
    """
    return closed_loop.published_gains(ROLL_TABLE, speed_m_s)


def rider_gains(system: str, speed_m_s: np.ndarray, step_m_s: float = 0.25
                ) -> tuple[np.ndarray, np.ndarray, str]:
    """Gains (n, 5), closed-loop stability (n,) and the control input of ``system``.

    Hands on: the rule gains, continued from 5 m/s on a ``step_m_s`` grid through every asked
    speed; hands free: :func:`hands_free_gains`.
    """
    v = np.asarray(speed_m_s, float)
    if system in HANDS_FREE:
        g = hands_free_gains(v)
        control = "roll"
    else:
        lo, hi = min(v.min(), 5.0), max(v.max(), 5.0)
        grid = np.union1d(np.arange(lo, hi + 1e-9, step_m_s), v)
        sweep = closed_loop.gain_sweep(system, grid)
        idx = np.searchsorted(sweep.speed_m_s, v)
        g = sweep.gains[idx]
        control = "steer"
    stable = np.zeros(len(v), bool)
    ok = np.isfinite(g).all(axis=1)
    if ok.any():
        a_cl, _ = closed_loop.closed_loop_matrices(system, v[ok], g[ok], control)
        stable[ok] = np.linalg.eigvals(a_cl).real.max(axis=1) < 0
    return g, stable, control


def measured_points(spectra_table: pd.DataFrame | None, published: dict,
                    measured_runs: pd.DataFrame | None, real_run: int = 3045) -> pd.DataFrame:
    """The measured points: system, speed_kmh, cadence_rpm, source, quantity, measured_rad."""
    rows = []
    t41 = published["table_4_1_model_validation"]
    for i, (sys_, v, c) in enumerate(zip(t41["system"], t41["speed_kmh"], t41["cadence_rpm"],
                                         strict=True)):
        for q in ("roll", "steer"):
            rows.append((sys_, float(v), float(c), TABLE_4_1_SOURCE, q,
                         float(t41[f"{q}_measured_rad"][i])))
    if measured_runs is not None:
        real = measured_runs[(measured_runs.run_id == real_run)
                             & (measured_runs.data_source != "synthetic")]
        for _, r in real.iterrows():
            for q in ("roll", "steer"):
                rows.append((r.system, float(r.speed_kmh), float(r.cadence_rpm),
                             f"run {real_run} ({r.data_source})", q,
                             float(r[f"{q}_measured_rad"])))
    if spectra_table is not None:
        for _, r in spectra_table.iterrows():
            for q in ("roll", "steer"):
                rows.append(("CF", float(r.speed_kmh), float(r.cadence_rpm), SPECTRA_SOURCE, q,
                             float(r[f"{q}_nearest_rad"])))
    return pd.DataFrame(rows, columns=["system", "speed_kmh", "cadence_rpm", "source",
                                       "quantity", "measured_rad"])


def _rd(measured: np.ndarray, model: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.abs(measured - model) / measured * 100.0


def model_amplitudes(system: str, speed_m_s: np.ndarray, cadence_rpm: np.ndarray,
                     harmonics: Sequence[int] = (1, 3, 5)) -> dict[str, np.ndarray]:
    """Open- and closed-loop roll and steer amplitudes at the cadence, point by point.

    Returns ``roll_open``, ``steer_open``, ``roll_closed``, ``steer_closed`` (rad) and
    ``stable`` (bool), each (n,).
    """
    v = np.asarray(speed_m_s, float)
    w = np.asarray(cadence_rpm, float) * np.pi / 30.0
    h = response.forcing(system, tuple(harmonics))
    k1 = int(np.nonzero(h.n == 1)[0][0])
    r_o, s_o = response.particular_solution(linear.linear_model(system), v, w, h)
    g, stable, control = rider_gains(system, v)
    roll_c = np.full(len(v), np.nan)
    steer_c = np.full(len(v), np.nan)
    for i in range(len(v)):
        if not np.isfinite(g[i]).all():
            continue
        r, s = closed_loop.closed_loop_particular(system, v[i:i + 1], g[i:i + 1], w[i:i + 1], h,
                                                  control)
        roll_c[i], steer_c[i] = abs(r[0, 0, k1]), abs(s[0, 0, k1])
    return {"roll_open": np.abs(r_o[:, k1]), "steer_open": np.abs(s_o[:, k1]),
            "roll_closed": roll_c, "steer_closed": steer_c, "stable": stable}


def validation_table(points: pd.DataFrame, harmonics: Sequence[int] = (1, 3, 5)) -> pd.DataFrame:
    """:data:`VALIDATION_COLUMNS` for the measured points (:func:`measured_points`)."""
    out = points.copy()
    for col in ("open_loop_rad", "closed_loop_rad"):
        out[col] = np.nan
    out["closed_loop_stable"] = False
    out["closed_loop_rider"] = ""
    for system, sub in points.groupby("system"):
        amps = model_amplitudes(system, sub.speed_kmh.to_numpy() / 3.6,
                                sub.cadence_rpm.to_numpy(), harmonics)
        q = sub.quantity.to_numpy()
        out.loc[sub.index, "open_loop_rad"] = np.where(q == "roll", amps["roll_open"],
                                                       amps["steer_open"])
        out.loc[sub.index, "closed_loop_rad"] = np.where(q == "roll", amps["roll_closed"],
                                                         amps["steer_closed"])
        out.loc[sub.index, "closed_loop_stable"] = amps["stable"]
        out.loc[sub.index, "closed_loop_rider"] = rider_of(system)
    out["rd_open_percent"] = _rd(out.measured_rad.to_numpy(), out.open_loop_rad.to_numpy())
    out["rd_closed_percent"] = _rd(out.measured_rad.to_numpy(), out.closed_loop_rad.to_numpy())
    return out[list(VALIDATION_COLUMNS)]


def table_4_2_closed(validation: pd.DataFrame) -> pd.DataFrame:
    """Table 4.2 beside its closed-loop counterpart: median and range (max - min) of the open-
    and closed-loop RD per system and measured source (closed-loop NaN rows left out)."""
    rows = []
    for (system, source), sub in validation.groupby(["system", "source"], sort=False):
        row = {"system": system, "source": source,
               "n_points": int((sub.quantity == "roll").sum())}
        for q in ("roll", "steer"):
            s = sub[sub.quantity == q]
            for kind in ("open", "closed"):
                x = s[f"rd_{kind}_percent"].dropna().to_numpy()
                row[f"{q}_rd_{kind}_median_percent"] = float(np.median(x)) if x.size else np.nan
                row[f"{q}_rd_{kind}_range_percent"] = float(np.ptp(x)) if x.size else np.nan
        rows.append(row)
    return pd.DataFrame(rows, columns=list(TABLE_4_2_CLOSED_COLUMNS))


def steer_stiffness_sweep(system: str, speed_m_s: float, cadence_rpm: float,
                          stiffness_n_m_rad: np.ndarray, harmonics: Sequence[int] = (1, 3, 5)
                          ) -> pd.DataFrame:
    """Cadence amplitudes with the steer-angle loop alone closed, against its gain.

    With only that loop closed the rider is ``u = -kDelta steer`` through the neuromuscular
    filter (static gain 1): a steer stiffness of ``kDelta`` N m/rad, the thesis's "the arms add
    ... stiffness" (Sec 4.2) as one number. ``kDelta = 0`` is the open loop.
    """
    model, geo = closed_loop.model_and_geometry(system)
    p = plant(model, geo, speed_m_s)
    h = response.forcing(system, tuple(harmonics))
    n, coef = response.harmonic_coefficients(h)
    k1 = int(np.nonzero(n == 1)[0][0])
    w = cadence_rpm * np.pi / 30.0
    rows = []
    eye = np.eye(N_STATES)
    for k in np.asarray(stiffness_n_m_rad, float):
        a = closed_matrix(p, np.array([k, 0, 0, 0, 0]), 1)
        x = np.linalg.solve(1j * w * n[k1] * eye - a, p.B_f @ coef[k1] * (n[k1] * w) ** 2)
        rows.append({"system": system, "speed_m_s": speed_m_s, "cadence_rpm": cadence_rpm,
                     "steer_stiffness_n_m_rad": k, "roll_rad": abs(x[0]), "steer_rad": abs(x[1]),
                     "stable": bool(np.linalg.eigvals(a[np.ix_(DYNAMIC, DYNAMIC)]).real.max()
                                    < 0)})
    return pd.DataFrame(rows)


#: Table 4.2's keys (columns of the thesis's table).
TABLE_4_2_KEYS: tuple[str, ...] = ("roll_rd_median_percent", "roll_rd_range_percent",
                                   "steer_rd_median_percent", "steer_rd_range_percent")


def matching_stiffness(sweep: pd.DataFrame) -> pd.DataFrame:
    """Per speed and quantity, the smallest steer stiffness (N m/rad) at which the steer-loop-only
    model's cadence amplitude falls to the measured one (linear interpolation on the sweep of
    :func:`steer_stiffness_sweep`; NaN where it never does, e.g. a measured amplitude above the
    open loop's)."""
    rows = []
    for v, sub in sweep.groupby("speed_kmh"):
        sub = sub.sort_values("steer_stiffness_n_m_rad")
        k = sub.steer_stiffness_n_m_rad.to_numpy()
        for q in ("roll", "steer"):
            model = sub[f"{q}_rad"].to_numpy()
            meas = float(sub[f"{q}_measured_rad"].iloc[0])
            below = np.nonzero(model <= meas)[0]
            if below.size == 0:
                k_match = np.nan
            elif below[0] == 0:
                k_match = 0.0
            else:
                i = below[0]
                k_match = float(np.interp(meas, [model[i], model[i - 1]], [k[i], k[i - 1]]))
            rows.append({"speed_kmh": v, "quantity": q, "measured_rad": meas,
                         "open_loop_rad": float(model[0]), "steer_stiffness_n_m_rad": k_match})
    return pd.DataFrame(rows)
