"""Reproduction-report rows of the closed loop: Table 4.2's CF column from Moore's measured
spectra and the rider-control gain rules against HumanControl's benchmark table (a module of its
own, so that only the report rule reaches the claims: editing a claim plans no closed-loop table
or figure)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .comparison import SPECTRA_SOURCE, TABLE_4_2_KEYS

__all__ = ["report_rows"]


def report_rows(t42_closed: pd.DataFrame, benchmark_gains_5: np.ndarray,
                spectra_reason: str = "") -> list:
    """Reproduction-report rows: Table 4.2's CF column from the measured spectra (open-loop RD,
    claims ``table_4_2.spectra.<key>.CF``) and the rule gains of the benchmark at 5.0 m/s
    against HumanControl's table (``rider.benchmark_gains_5ms.<gain>``)."""
    from .. import report

    rows = []
    cf = t42_closed[(t42_closed.system == "CF") & (t42_closed.source == SPECTRA_SOURCE)]
    note = ("open-loop RD of the CF model against Moore's measured spectra: one 60 s run per belt "
            "speed (2-30 km/h), nearest bin at the drawn cadence, unwindowed 2|X|/N amplitude; "
            "the thesis's CF runs are not known")
    for key in TABLE_4_2_KEYS:
        q, stat = key.split("_rd_")
        col = f"{q}_rd_open_{stat}"
        quantity = key.replace("_", " ")
        if cf.empty:
            rows.append(report.check("table_4_2.spectra.{key}.CF", None, key=key,
                                     quantity=quantity, unavailable=spectra_reason
                                     or "measured spectra not available"))
        else:
            rows.append(report.check("table_4_2.spectra.{key}.CF", float(cf[col].iloc[0]),
                                     key=key, quantity=quantity, note=note))
    for j, name in enumerate(("kDelta", "kPhiDot", "kPhi", "kPsi", "kY"), start=1):
        rows.append(report.check("rider.benchmark_gains_5ms.{gain}",
                                 float(benchmark_gains_5[j - 1]), gain=name, j=j,
                                 note="HumanControl generate_data.m rules on the Meijaard "
                                      "benchmark at 5.0 m/s (pedalrepro.rider.gains)"))
    return rows
