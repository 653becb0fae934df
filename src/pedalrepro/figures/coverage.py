"""How many of the thesis's figure ids this build shows, and how completely (the reproduction
report page's figure count).

Kept apart from :mod:`pedalrepro.figures.registry`: it reads the report's id list
(:func:`pedalrepro.report.figure_coverage`, ``data/figure_ids.yaml``) and so the report's data,
which no figure rule depends on.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from .. import report
from .registry import COMPLETE, FIGURES, MISSING, completeness

__all__ = ["coverage"]


def coverage(root: str | Path | None = None) -> pd.DataFrame:
    """:func:`pedalrepro.report.figure_coverage` (every thesis id, ``present``) plus ``status``
    ``complete`` / ``partial`` / ``missing`` and ``lacking`` (what a partial figure lacks: a
    method or panel the thesis shows; :func:`pedalrepro.figures.registry.completeness`) - the
    report page's figure count."""
    ids = report.figure_coverage(root)
    status, lacking = [], []
    for fid, present in zip(ids["id"], ids["present"], strict=True):
        if fid in FIGURES:
            st, what = completeness(fid, root)
        else:  # a table
            st, what = (COMPLETE if present else MISSING), []
        status.append(st)
        lacking.append(", ".join(what))
    ids["status"] = status
    ids["lacking"] = lacking
    return ids
