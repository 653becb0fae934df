"""Reproduction-report rows of chapter 4 (Tables 4.1 and 4.2, the real public-subset run).

Kept apart from :mod:`pedalrepro.validation` (the tables): the rows are checked against
``data/published/claims.yaml`` (:func:`pedalrepro.report.check`), and the rule writing them
(``validation_report``) only reads, so no table or figure depends on the claims.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from . import params, report

__all__ = ["NOT_MEASUREMENT", "chapter_4_rows", "real_report_rows", "report_rows"]

NOT_MEASUREMENT = ("figshare unreachable from this machine; the synthetic stand-in is not the "
                   "measurement")


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

    def check(claim_id: str, value: float, **fields) -> report.Row:
        # a SYNTHETIC value never stands in the "reproduced" cell beside a published number: the
        # cell says n/a and the note gives the stand-in's value, labelled
        if not synthetic:
            return report.check(claim_id, value, **fields)
        c = report.claim(claim_id)
        return report.check(c, None, unavailable=why,
                            note=f"{why}. SYNTHETIC stand-in value: {c.fmt.format(value)} "
                                 "(not a measurement, not compared)", **fields)

    pub = published["table_4_1_model_validation"]
    runs = t41[~t41.system.isin(["median", "range"])].reset_index(drop=True)
    for i, (sys_, v) in enumerate(zip(pub["system"], pub["speed_kmh"], strict=True)):
        hit = runs[(runs.system == sys_) & np.isclose(runs.speed_kmh, float(v))]
        if hit.empty:
            raise ValueError(f"Table 4.1 lacks {sys_} at {v} km/h")
        row = hit.iloc[0]
        for q in ("roll", "steer"):
            rows.append(check(
                "table_4_1.measured.{coord}.{system}_{speed}", float(row[f"{q}_measured_rad"]),
                coord=q, system=sys_, speed=v, i=i))
    for q in ("roll", "steer"):
        got = float(t41.loc[t41.system == "median", f"{q}_rd_percent"].iloc[0])
        rows.append(check("table_4_1.median_rd.{coord}", got, coord=q))
    p42 = published["table_4_2_open_vs_closed_loop"]
    for i, sys_ in enumerate(p42["systems"]):
        hit = t42[t42.system == sys_]
        for key in ("roll_rd_median_percent", "roll_rd_range_percent",
                    "steer_rd_median_percent", "steer_rd_range_percent"):
            rows.append(check(
                "table_4_2.{key}.{system}", float(hit[key].iloc[0]), key=key, system=sys_, i=i,
                quantity=key.replace("_", " ")))
    return rows


def real_report_rows(comparison: pd.DataFrame, published: dict | None = None
                     ) -> list[report.Row]:
    """Report rows of a real public-subset run (thesis method): its cadence, roll and steer
    against the Table 4.1 column of the same belt speed, and against the column it matches best
    when that is another one (claims ``table_4_1.real_run_{run}.*`` of
    ``data/published/claims.yaml``); the notes name the best column of both methods.
    ``published``: :func:`pedalrepro.params.published` (default: read it)."""
    pub = (published or params.published())["table_4_1_model_validation"]
    rows: list[report.Row] = []
    for rid, comp in comparison.groupby("run_id"):
        th = comp[comp.method == "thesis"]
        best = {m: comp[comp.method == m].sort_values("n_matches", ascending=False,
                                                      kind="stable").iloc[0]
                for m in ("thesis", "exact")}
        note = "; ".join(f"{m} method: best match {b.column} ({b.n_matches} of 3)"
                         for m, b in best.items())
        picks = [(r, "same belt speed") for _, r in th[th.belt_speed_matches].iterrows()]
        if not best["thesis"].belt_speed_matches:
            picks.append((best["thesis"], "best-matching column"))
        for s, why in picks:
            system = s.column.split()[0]
            hit = [i for i, (sy, v) in enumerate(zip(pub["system"], pub["speed_kmh"],
                                                     strict=True))
                   if sy == system and abs(float(v) - s.speed_published_kmh) <= 0.05]
            if len(hit) != 1:
                raise ValueError(f"Table 4.1 has no single column {s.column!r} "
                                 "(thesis_values.yaml: table_4_1_model_validation)")
            fields = dict(run=int(rid), system=system, speed=f"{s.speed_published_kmh:g}",
                          i=hit[0], why=why, belt=f"{s.speed_kmh:.1f}")
            rows.append(report.check("table_4_1.real_run_{run}.cadence.{system}_{speed}",
                                     float(s.cadence_rpm), note=f"public subset (real); {note}",
                                     **fields))
            for q in ("roll", "steer"):
                rows.append(report.check(
                    "table_4_1.real_run_{run}.{coord}_measured.{system}_{speed}",
                    float(s[f"{q}_rad"]), coord=q, note=f"public subset (real); {note}",
                    **fields))
    return rows


def chapter_4_rows(tables: dict, source: dict, published: dict) -> list[report.Row]:
    """Every chapter-4 report row from :func:`pedalrepro.validation.chapter_4_tables`'s tables:
    Table 4.1 and 4.2 of the main source (:func:`report_rows`), then the real public-subset
    run's rows when it has a comparison (:func:`real_report_rows`)."""
    ds = source["data_source"]
    t41 = tables["t41"]
    rows = report_rows(t41[t41.data_source == ds], tables["t42"], published, ds,
                       "" if ds == "figshare" else source["reason"])
    if not tables["comparison"].empty:
        rows += real_report_rows(tables["comparison"])
    return rows
