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
from pathlib import Path

import numpy as np
import pandas as pd

from . import disturbance, linear, params, response

__all__ = [
    "TABLE_4_1_COLUMNS", "TABLE_4_2_COLUMNS", "DATA_LABELS", "labelled", "caption", "rd_percent",
    "model_response", "model_amplitudes", "model_series", "per_run_table", "table_4_1", "table_4_2",
    "example_runs", "ps_map", "PUBLIC", "COMPARISON_COLUMNS", "real_rows", "published_columns",
    "method_comparison", "chapter_4_tables", "chapter_4_from_files", "real_example",
]

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
#: What a table shows for each ``data_source`` value in its first column (:func:`labelled`).
DATA_LABELS: dict[str, str] = {"synthetic": "SYNTHETIC", "figshare": "measured",
                               "public_subset": "measured (public subset)"}


def labelled(table: pd.DataFrame) -> pd.DataFrame:
    """A chapter-4 table as the book shows it: its first column ``data`` says where each row's
    measured values come from (``SYNTHETIC``, ``measured`` or ``measured (public subset)``,
    :data:`DATA_LABELS`), in place of the last column ``data_source``.

    Examples
    --------
    >>> t = pd.DataFrame({"system": ["HR", "HR"], "data_source": ["synthetic", "public_subset"]})
    >>> labelled(t).to_dict("list")
    {'data': ['SYNTHETIC', 'measured (public subset)'], 'system': ['HR', 'HR']}
    """
    if "data_source" not in table:
        raise KeyError("labelled() needs the column data_source")
    unknown = set(table["data_source"]) - set(DATA_LABELS)
    if unknown:
        raise ValueError(f"unknown data_source values {sorted(unknown)}")
    out = table.drop(columns="data_source")
    out.insert(0, "data", table["data_source"].map(DATA_LABELS).to_numpy())
    return out


def caption(text: str, data_sources) -> str:
    """A table or figure caption led by ``SYNTHETIC:`` when any of its rows comes from the
    stand-in (the label must be seen where the table is, not in its last column).

    >>> caption("Table.", ["synthetic", "public_subset"])
    'SYNTHETIC (stand-in, not the measurement) except rows marked measured: Table.'
    >>> caption("Table.", ["figshare"])
    'Table.'
    """
    sources = set(data_sources)
    if "synthetic" not in sources:
        return text
    if sources == {"synthetic"}:
        return "SYNTHETIC (stand-in, not the measurement): " + text
    return "SYNTHETIC (stand-in, not the measurement) except rows marked measured: " + text


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


#: ``data_source`` of the rows built from the real public subset (pedalrepro.mocap.prepare).
PUBLIC = "public_subset"
#: Columns of :func:`method_comparison` (``mocap_real_comparison.csv``, empty without a real run).
COMPARISON_COLUMNS: tuple[str, ...] = (
    "run_id", "method", "column", "speed_kmh", "cadence_rpm", "roll_rad", "steer_rad",
    "speed_published_kmh", "cadence_published_rpm", "roll_published_rad", "steer_published_rad",
    "belt_speed_matches", "cadence_matches", "roll_matches", "steer_matches", "n_matches",
)


def real_rows(measured: pd.DataFrame, systems: Sequence[str] = ("HR", "CR")) -> pd.DataFrame:
    """Table 4.1 rows of real public-subset runs (``data_source == "public_subset"``).

    The model is evaluated at the run's belt speed and measured cadence (``cadence_rpm`` =
    ``cadence_measured_rpm``: there is no table-header cadence for such a run); the rows are
    never part of the median and range rows of the main source.
    """
    sub = measured[(measured.data_source == PUBLIC) & measured.system.isin(systems)]
    rows = []
    for _, m in sub.iterrows():
        roll_m, steer_m = model_amplitudes(m.system, m.speed_kmh / 3.6, m.cadence_rpm * np.pi / 30)
        row = {"system": m.system, "speed_kmh": float(m.speed_kmh),
               "cadence_rpm": float(m.cadence_rpm), "cadence_measured_rpm": float(m.cadence_rpm),
               "roll_measured_rad": float(m.roll_measured_rad), "roll_model_rad": float(roll_m),
               "steer_measured_rad": float(m.steer_measured_rad),
               "steer_model_rad": float(steer_m), "data_source": PUBLIC}
        for q in ("roll", "steer"):
            row[f"{q}_difference_rad"] = row[f"{q}_measured_rad"] - row[f"{q}_model_rad"]
            row[f"{q}_rd_percent"] = float(rd_percent([row[f"{q}_measured_rad"]],
                                                      [row[f"{q}_model_rad"]])[0])
        rows.append(row)
    return pd.DataFrame(rows, columns=list(TABLE_4_1_COLUMNS))


def published_columns(published: dict, system: str) -> pd.DataFrame:
    """Table 4.1's columns of one system: ``speed_kmh, cadence_rpm, roll_measured_rad,
    steer_measured_rad`` as printed."""
    pub = published["table_4_1_model_validation"]
    idx = [i for i, s in enumerate(pub["system"]) if s == system]
    return pd.DataFrame({k: [float(pub[k][i]) for i in idx] for k in
                         ("speed_kmh", "cadence_rpm", "roll_measured_rad", "steer_measured_rad")})


def method_comparison(row: pd.Series, published: dict) -> pd.DataFrame:
    """A real run's cadence and amplitudes by both methods against every Table 4.1 column of
    its system.

    Methods: ``thesis`` = the Hann DFT bin nearest the whole-bin cadence (Sec 3.1.2.1.1; the
    cadence as printed, whole rpm); ``exact`` = the Hann DFT at the interpolated cadence
    (this project). A value *matches* a printed one when it rounds to it (cadence to whole rpm,
    amplitudes to 3 decimals, i.e. within half the last digit). Columns: ``method, column,
    speed_kmh, cadence_rpm, roll_rad, steer_rad`` (the run's), the printed ones
    (``*_published``), per-quantity ``*_matches`` and ``n_matches`` (of 3: cadence, roll,
    steer), and ``belt_speed_matches``.
    """
    cols = published_columns(published, row.system)
    by_method = {
        "thesis": (float(row.cadence_bin_rpm), float(row.roll_bin_rad), float(row.steer_bin_rad)),
        "exact": (float(row.cadence_rpm), float(row.roll_measured_rad),
                  float(row.steer_measured_rad)),
    }
    out = []
    for method, (cad, roll, steer) in by_method.items():
        for _, c in cols.iterrows():
            r = {"run_id": int(row.run_id), "method": method,
                 "column": f"{row.system} {c.speed_kmh:g} km/h", "speed_kmh": float(row.speed_kmh),
                 "cadence_rpm": cad, "roll_rad": roll, "steer_rad": steer,
                 "speed_published_kmh": c.speed_kmh, "cadence_published_rpm": c.cadence_rpm,
                 "roll_published_rad": c.roll_measured_rad,
                 "steer_published_rad": c.steer_measured_rad}
            r["belt_speed_matches"] = bool(abs(r["speed_kmh"] - c.speed_kmh) <= 0.05)
            r["cadence_matches"] = bool(abs(cad - c.cadence_rpm) <= 0.5)
            r["roll_matches"] = bool(abs(roll - c.roll_measured_rad) <= 5e-4)
            r["steer_matches"] = bool(abs(steer - c.steer_measured_rad) <= 5e-4)
            r["n_matches"] = int(r["cadence_matches"] + r["roll_matches"] + r["steer_matches"])
            out.append(r)
    return pd.DataFrame(out, columns=list(COMPARISON_COLUMNS))


def chapter_4_tables(measured: pd.DataFrame, selection: pd.DataFrame, model: pd.DataFrame,
                     source: dict, published: dict) -> dict:
    """Every chapter-4 table from the per-run extraction (the rule ``validation_tables``).

    The main source's rows (``source["data_source"]``) make Table 4.1's seven runs with their
    median and range, Table 4.2 and the per-run table; real public-subset rows follow in
    Table 4.1 and the per-run table with their own ``data_source`` and are never pooled.

    Returns ``t41, t42, per_run, comparison`` (DataFrames); their report rows are
    :func:`pedalrepro.validation_report.chapter_4_rows` (the rule ``validation_report``).
    """
    ds = source["data_source"]
    main = measured[measured.data_source == ds]
    real = measured[measured.data_source == PUBLIC]
    t41 = table_4_1(main, selection, model, ds)
    per_run = per_run_table(main, ds)
    t42 = table_4_2(per_run, ds)
    comparison = pd.DataFrame(columns=list(COMPARISON_COLUMNS))
    if not real.empty:
        t41 = pd.concat([t41, real_rows(real)], ignore_index=True)
        per_run = pd.concat([per_run, per_run_table(real, PUBLIC)], ignore_index=True)
        comparison = pd.concat([method_comparison(r, published) for _, r in real.iterrows()
                                if r.system in set(published["table_4_1_model_validation"]
                                                   ["system"])], ignore_index=True)
    return {"t41": t41, "t42": t42, "per_run": per_run, "comparison": comparison}


def chapter_4_from_files(measured_csv: str | Path, runs_dir: str | Path, source_json: str | Path,
                         model_csv: str | Path, published: dict | None = None
                         ) -> tuple[dict, dict]:
    """:func:`chapter_4_tables` from the treadmill part's files: the per-run extraction
    (``mocap/measured.csv``), the run files (``mocap/runs``, for Table 4.1's run selection), the
    data source record (``mocap/source.json``) and the linear part's ``table_4_1_model.csv``.
    Returns ``(tables, source)``; what the rules ``validation_tables`` (the tables) and
    ``validation_report`` (their report rows) both start from."""
    import json

    from .mocap import runs

    source = json.loads(Path(source_json).read_text())
    measured = pd.read_csv(measured_csv)
    main = measured[measured.data_source == source["data_source"]]
    selection = runs.table_4_1_runs(runs.index_runs(runs_dir),
                                    dict(zip(main.run_id, main.cadence_rpm, strict=True)))
    tables = chapter_4_tables(measured, selection, pd.read_csv(model_csv), source,
                              published or params.published())
    return tables, source


def real_example(per_run: pd.DataFrame, series) -> dict[str, np.ndarray] | None:
    """The first real public-subset run of the per-run table with its model series (the REAL
    panel's data, :func:`pedalrepro.figdata.validation`); ``None`` when the build has none.
    ``series``: the extraction's ``series.npz`` (keys ``<series_id>_<name>``). Keys:
    ``real_run_id``, ``real_system``, ``real_speed_kmh``, ``real_cadence_rpm``, ``real_t_s``,
    ``real_roll_rad``, ``real_steer_rad``, ``real_model_roll_rad``, ``real_model_steer_rad``.
    Plain arrays, so this module needs nothing from :mod:`pedalrepro.figures` (whose style
    file would otherwise become an input of every rule that reads a table here)."""
    sub = per_run[per_run.data_source == PUBLIC]
    if sub.empty:
        return None
    row = sub.iloc[0]
    key = f"public_{int(row.run_id)}"
    mr, ms = model_series(row.system, row.speed_kmh / 3.6, series[f"{key}_crank_rad"],
                          row.cadence_rpm * np.pi / 30)
    return dict(real_run_id=np.int64(row.run_id), real_system=np.str_(row.system),
                real_speed_kmh=np.float64(row.speed_kmh),
                real_cadence_rpm=np.float64(row.cadence_rpm), real_t_s=series[f"{key}_t_s"],
                real_roll_rad=series[f"{key}_roll_rad"], real_steer_rad=series[f"{key}_steer_rad"],
                real_model_roll_rad=mr, real_model_steer_rad=ms)
