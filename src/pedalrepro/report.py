"""The reproduction report: every published number beside the project's value, with a status.

Each part of the pipeline writes its own rows to ``results/tables/report/<part>.csv`` with
:func:`write_rows`; the ``report`` rule joins them into ``results/tables/reproduction_report.csv``
with :func:`combine`. Published values come from ``data/published``; reproduced values are
computed by the pipeline, never typed in.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd

COLUMNS: tuple[str, ...] = (
    "item", "section", "published", "reproduced", "tolerance", "status", "note",
)
#: The allowed statuses.
REPRODUCED = "reproduced"
DIFFERS = "differs"
NOT_REPRODUCIBLE = "not reproducible here"
STATUSES: tuple[str, ...] = (REPRODUCED, DIFFERS, NOT_REPRODUCIBLE)


@dataclass
class Row:
    """One line of the reproduction report.

    ``published`` and ``reproduced`` are strings so that ranges ("0.1-5 %") and numbers sit in one
    column; ``tolerance`` says how the two were compared; ``note`` explains a difference.
    """

    item: str
    section: str
    published: str
    reproduced: str
    tolerance: str
    status: str
    note: str = ""

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status {self.status!r} not in {STATUSES}")


def compare(
    item: str,
    section: str,
    published: float,
    reproduced: float,
    *,
    rel: float | None = None,
    abs_: float | None = None,
    fmt: str = "{:.6g}",
    note: str = "",
) -> Row:
    """A report row for one number, status from a relative and/or absolute tolerance.

    ``reproduced`` must be finite: a NaN is a failure of the pipeline, not a table entry.
    """
    if not np.isfinite(reproduced):
        raise ValueError(f"report item {item!r}: reproduced value is not finite ({reproduced})")
    diff = abs(reproduced - published)
    ok = True
    tol = []
    if rel is not None:
        ok &= diff <= rel * abs(published)
        tol.append(f"rel {rel:g}")
    if abs_ is not None:
        ok &= diff <= abs_
        tol.append(f"abs {abs_:g}")
    if not tol:
        raise ValueError("compare() needs rel= or abs_=")
    return Row(item, section, fmt.format(published), fmt.format(reproduced), ", ".join(tol),
               REPRODUCED if ok else DIFFERS, note)


def write_rows(rows: Iterable[Row], path: str | Path) -> pd.DataFrame:
    """Write report rows to ``path`` (CSV with :data:`COLUMNS`) and return them as a DataFrame."""
    df = pd.DataFrame([asdict(r) for r in rows], columns=list(COLUMNS))
    if df.empty:
        raise ValueError(f"no report rows for {path}")
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False)
    return df


def combine(parts: Sequence[str | Path], out: str | Path) -> pd.DataFrame:
    """Join report parts into the reproduction report, checking columns and statuses."""
    frames = []
    for part in parts:
        df = pd.read_csv(part, dtype=str, keep_default_na=False)
        if list(df.columns) != list(COLUMNS):
            raise ValueError(f"{part}: columns {list(df.columns)} != {list(COLUMNS)}")
        bad = set(df["status"]) - set(STATUSES)
        if bad:
            raise ValueError(f"{part}: unknown status {sorted(bad)}")
        frames.append(df)
    report = pd.concat(frames, ignore_index=True)
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    report.to_csv(out, index=False)
    return report


def summary(report: pd.DataFrame) -> dict[str, int]:
    """Count of rows per status (every status present, zeros included)."""
    counts = report["status"].value_counts()
    return {s: int(counts.get(s, 0)) for s in STATUSES}
