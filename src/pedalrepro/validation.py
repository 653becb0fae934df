"""Open-loop model vs treadmill measurement: Tables 4.1 and 4.2 (Sec 4.1-4.2).

Measured amplitudes: Hann-windowed DFT of the roll and steer angles extracted from the markers
(:mod:`pedalrepro.mocap`) at the run's detected cadence. Model amplitudes: the particular solution
of the system's Appendix B model at the run's speed and cadence, driven by the pedalling torques of
Eq 3.14 (:func:`pedalrepro.response.particular_solution`,
:func:`pedalrepro.disturbance.torque_harmonics`); for Table 4.1 the model columns are the linear
part's ``table_4_1_model.csv``. Relative difference (Table 4.1 caption, Eq 3.26):
``RD = |measured - model| / measured * 100``.

Every table carries a ``data_source`` column (``figshare`` or ``synthetic``): rows built from the
synthetic stand-in are not measurements.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from . import disturbance, linear, params, report, response

TABLE_4_1_COLUMNS: tuple[str, ...] = (
    "system", "speed_kmh", "cadence_rpm", "cadence_measured_rpm", "roll_measured_rad",
    "roll_model_rad",
    "roll_difference_rad", "roll_rd_percent", "steer_measured_rad", "steer_model_rad",
    "steer_difference_rad", "steer_rd_percent", "data_source",
)
TABLE_4_2_COLUMNS: tuple[str, ...] = (
    "system", "n_runs", "roll_rd_median_percent", "roll_rd_range_percent",
    "steer_rd_median_percent", "steer_rd_range_percent", "data_source",
)
NOT_MEASUREMENT = ("figshare unreachable from this machine; the synthetic stand-in is not the "
                   "measurement")


def rd_percent(measured, model) -> np.ndarray:
    """Relative difference ``|measured - model| / measured * 100`` (Table 4.1 caption)."""
    measured = np.asarray(measured, float)
    if np.any(measured <= 0) or not np.all(np.isfinite(measured)):
        raise ValueError("RD needs positive, finite measured amplitudes")
    return np.abs(measured - np.asarray(model, float)) / measured * 100.0


def model_response(system: str, speed_m_s, cadence_rad_s, harmonics=(1, 3, 5)
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Harmonic numbers and complex roll and steer particular solutions (Sec 3.1.2.2.1).

    ``speed_m_s`` and ``cadence_rad_s`` broadcast; the last axis of roll/steer is the harmonic.
    """
    h = disturbance.torque_harmonics(params.BICYCLE_OF_MODEL[system], harmonics=harmonics)
    roll, steer = response.particular_solution(linear.linear_model(system), speed_m_s,
                                               cadence_rad_s, h)
    return np.asarray(h.n), roll, steer


def model_amplitudes(system: str, speed_m_s, cadence_rad_s) -> tuple[np.ndarray, np.ndarray]:
    """Roll and steer particular-solution amplitudes at the cadence (rad), batched."""
    n, roll, steer = model_response(system, speed_m_s, cadence_rad_s)
    k = int(np.flatnonzero(n == 1)[0])
    return np.abs(roll[..., k]), np.abs(steer[..., k])


def model_series(system: str, speed_m_s: float, crank_rad: np.ndarray, cadence_rad_s: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Steady-state model roll and steer (rad) phase-locked to a measured crank angle.

    The model's time origin has the right foot forward (``theta_A = 0``) and
    ``theta_A = -w t`` (Sec 2.1.1), so ``exp(i n w t) = exp(-i n theta_A)``.
    """
    n, roll, steer = model_response(system, speed_m_s, cadence_rad_s)
    ph = np.exp(-1j * np.multiply.outer(np.asarray(crank_rad, float), n))
    return np.real(ph @ roll), np.real(ph @ steer)


def per_run_table(measured: pd.DataFrame, data_source: str) -> pd.DataFrame:
    """Measured and model cadence amplitudes and RD of every run of the four systems.

    ``measured`` columns: ``run_id, system, speed_kmh, cadence_rpm, roll_measured_rad,
    steer_measured_rad`` (from the extraction); the model is evaluated at each run's belt speed
    and detected cadence.
    """
    df = measured[measured.system.isin(params.MODELS)].copy()
    if df.empty:
        raise ValueError("no run of the systems HS, CF, HR, CR to compare")
    roll_m = np.empty(len(df))
    steer_m = np.empty(len(df))
    for system, idx in df.groupby("system").indices.items():
        sub = df.iloc[idx]
        r, s = model_amplitudes(system, sub.speed_kmh.to_numpy() / 3.6,
                                sub.cadence_rpm.to_numpy() * np.pi / 30)
        roll_m[idx], steer_m[idx] = r, s
    df["roll_model_rad"] = roll_m
    df["steer_model_rad"] = steer_m
    df["roll_rd_percent"] = rd_percent(df.roll_measured_rad, roll_m)
    df["steer_rd_percent"] = rd_percent(df.steer_measured_rad, steer_m)
    df["data_source"] = data_source
    return df.reset_index(drop=True)


def table_4_1(measured: pd.DataFrame, selection: pd.DataFrame, model: pd.DataFrame,
              data_source: str) -> pd.DataFrame:
    """Table 4.1: measured and model amplitudes of the seven hands-free runs, median and range.

    ``cadence_rpm`` is the table header's cadence (the model's input);
    ``cadence_measured_rpm`` the cadence detected in the selected run.

    Parameters
    ----------
    measured
        Per-run extraction (``run_id``, ``cadence_rpm``, ``roll_measured_rad``,
        ``steer_measured_rad``).
    selection
        :func:`pedalrepro.mocap.runs.table_4_1_runs`: ``system, speed_kmh, cadence_rpm, run_id``.
    model
        The linear part's ``table_4_1_model.csv`` (``system, speed_kmh, cadence_rpm,
        roll_model_rad, steer_model_rad``).
    """
    meas = measured[["run_id", "cadence_rpm", "roll_measured_rad", "steer_measured_rad"]]
    df = selection.merge(meas.rename(columns={"cadence_rpm": "cadence_measured_rpm"}),
                         on="run_id", how="left", validate="one_to_one")
    if df[["roll_measured_rad", "steer_measured_rad"]].isna().any().any():
        missing = df.loc[df.roll_measured_rad.isna(), "run_id"].tolist()
        raise ValueError(f"Table 4.1 runs without a measurement: {missing}")
    m = model[["system", "speed_kmh", "roll_model_rad", "steer_model_rad"]].copy()
    m["speed_kmh"] = m.speed_kmh.astype(float).round(3)
    df["speed_kmh"] = df.speed_kmh.astype(float).round(3)
    df = df.merge(m, on=["system", "speed_kmh"], how="left", validate="one_to_one")
    if df[["roll_model_rad", "steer_model_rad"]].isna().any().any():
        raise ValueError("table_4_1_model.csv lacks a Table 4.1 condition: "
                         f"{df.loc[df.roll_model_rad.isna(), ['system', 'speed_kmh']].values}")
    for q in ("roll", "steer"):
        df[f"{q}_difference_rad"] = df[f"{q}_measured_rad"] - df[f"{q}_model_rad"]
        df[f"{q}_rd_percent"] = rd_percent(df[f"{q}_measured_rad"], df[f"{q}_model_rad"])
    df["data_source"] = data_source
    df = df[list(TABLE_4_1_COLUMNS)]
    num = [c for c in TABLE_4_1_COLUMNS if c not in ("system", "data_source")]
    med = {"system": "median", **{c: float(np.median(df[c])) for c in num},
           "data_source": data_source}
    rng = {"system": "range", **{c: float(np.ptp(df[c])) for c in num},
           "data_source": data_source}
    return pd.concat([df, pd.DataFrame([med, rng])], ignore_index=True)


def table_4_2(per_run: pd.DataFrame, data_source: str,
              systems: Sequence[str] = params.MODELS) -> pd.DataFrame:
    """Table 4.2: median and range (max - min) of the RD per system, over all its runs."""
    rows = []
    for system in systems:
        sub = per_run[per_run.system == system]
        if sub.empty:
            raise ValueError(f"no run of system {system} for Table 4.2")
        rows.append({
            "system": system, "n_runs": len(sub),
            "roll_rd_median_percent": float(np.median(sub.roll_rd_percent)),
            "roll_rd_range_percent": float(np.ptp(sub.roll_rd_percent)),
            "steer_rd_median_percent": float(np.median(sub.steer_rd_percent)),
            "steer_rd_range_percent": float(np.ptp(sub.steer_rd_percent)),
            "data_source": data_source,
        })
    return pd.DataFrame(rows, columns=list(TABLE_4_2_COLUMNS))


def report_rows(t41: pd.DataFrame, t42: pd.DataFrame, published: dict, data_source: str,
                reason: str = "") -> list[report.Row]:
    """Reproduction-report rows: Table 4.1 (measured columns, median RD) and Table 4.2.

    Measured quantities built from the synthetic stand-in get the status ``not reproducible
    here`` with the reason; from the real data they are compared by the checks of
    ``data/published/claims.yaml`` (ids ``table_4_1.measured.*``, ``table_4_1.median_rd.*``,
    ``table_4_2.*``). The model columns are the linear part's rows
    ("Table 4.1 <column> <roll|steer> model", ``rules/scripts/linear_report.py``), not repeated
    here.
    """
    rows: list[report.Row] = []
    synthetic = data_source != "figshare"
    why = (reason or NOT_MEASUREMENT) if synthetic else None
    label = " (synthetic)" if synthetic else ""
    pub = published["table_4_1_model_validation"]
    runs = t41[~t41.system.isin(["median", "range"])].reset_index(drop=True)
    for i, (sys_, v) in enumerate(zip(pub["system"], pub["speed_kmh"], strict=True)):
        hit = runs[(runs.system == sys_) & np.isclose(runs.speed_kmh, float(v))]
        if hit.empty:
            raise ValueError(f"Table 4.1 lacks {sys_} at {v} km/h")
        row = hit.iloc[0]
        for q in ("roll", "steer"):
            rows.append(report.check(
                "table_4_1.measured.{coord}.{system}_{speed}", float(row[f"{q}_measured_rad"]),
                coord=q, system=sys_, speed=v, i=i, label=label, unavailable=why))
    for q in ("roll", "steer"):
        got = float(t41.loc[t41.system == "median", f"{q}_rd_percent"].iloc[0])
        rows.append(report.check("table_4_1.median_rd.{coord}", got, coord=q, label=label,
                                 unavailable=why))
    p42 = published["table_4_2_open_vs_closed_loop"]
    for i, sys_ in enumerate(p42["systems"]):
        hit = t42[t42.system == sys_]
        for key in ("roll_rd_median_percent", "roll_rd_range_percent",
                    "steer_rd_median_percent", "steer_rd_range_percent"):
            rows.append(report.check(
                "table_4_2.{key}.{system}", float(hit[key].iloc[0]), key=key, system=sys_, i=i,
                quantity=key.replace("_", " "), label=label, unavailable=why))
    return rows


def example_runs(per_run: pd.DataFrame, system: str, n: int = 6) -> pd.DataFrame:
    """Up to ``n`` runs of a system spread evenly over its speeds (Figs 4.2-4.9)."""
    sub = per_run[per_run.system == system].sort_values(["speed_kmh", "run_id"])
    if sub.empty:
        raise ValueError(f"no run of system {system}")
    pick = np.unique(np.linspace(0, len(sub) - 1, min(n, len(sub))).round().astype(int))
    return sub.iloc[pick].reset_index(drop=True)


def ps_map(system: str, speed_m_s: np.ndarray, omega_rad_s: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """Particular-solution roll and steer amplitude maps ``(n_v, n_w)`` (one batched solve)."""
    return model_amplitudes(system, np.asarray(speed_m_s)[:, None],
                            np.asarray(omega_rad_s)[None, :])
