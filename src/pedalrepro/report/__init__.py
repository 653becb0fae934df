"""The reproduction report: every published number beside the project's value, with a status.

Each published claim has an id and a check in ``data/published/claims.yaml``;
:func:`check` (:mod:`~pedalrepro.report.claims`) turns a claim and the pipeline's value into a
report :class:`Row` and is the only place where a status is decided; the five statuses are
defined in :mod:`~pedalrepro.report.statuses`. Each part of the pipeline writes its rows to
``results/tables/report/<part>.csv`` with :func:`write_rows`; the ``report`` rule joins them into
``results/tables/reproduction_report.csv`` with :func:`combine` (:mod:`~pedalrepro.report.rows`).
The pinned statuses of ``tests/expected_status.csv`` and the ``report-status`` command live in
:mod:`~pedalrepro.report.pinned`, the book's HTML of rows in :mod:`~pedalrepro.report.html`.
Reproduced values are computed by the pipeline, never typed in.
"""

from __future__ import annotations

from . import claims as claims_module
from .claims import (
                     CHECK_KINDS,
                     DATA_FILES,
                     KINDS,
                     Claim,
                     Kind,
                     check,
                     claim,
                     claims,
                     published_value,
)
from .html import REPORT_PAGE, anchor, legend_html, links_html, rows_html
from .pinned import (
                     EXPECTED_STATUS_FILE,
                     PROFILES,
                     add_cli,
                     expected_status,
                     profile_of,
                     status_changes,
                     update_expected_status,
                     validate_report,
)
from .rows import (
                     CHAPTERS,
                     COLUMNS,
                     Row,
                     book_pages,
                     by_id,
                     combine,
                     figure_coverage,
                     figure_ids,
                     load,
                     select,
                     summary,
                     thesis_chapter,
                     write_rows,
)
from .statuses import (
                     CALIBRATED,
                     CONSISTENT,
                     DIFFERS,
                     MEANING,
                     NOT_REPRODUCIBLE,
                     PRECISE_LIMIT,
                     REPRODUCED,
                     STATUSES,
)

__all__ = [
    "CALIBRATED", "CHAPTERS", "CHECK_KINDS", "COLUMNS", "CONSISTENT", "DATA_FILES", "DIFFERS",
    "EXPECTED_STATUS_FILE", "KINDS", "MEANING", "NOT_REPRODUCIBLE", "PRECISE_LIMIT", "PROFILES",
    "REPORT_PAGE", "REPRODUCED", "STATUSES", "Claim", "Kind", "Row", "add_cli", "anchor",
    "book_pages", "by_id", "check", "claim", "claims", "claims_module", "combine",
    "expected_status", "figure_coverage", "figure_ids", "legend_html",
    "links_html", "load", "profile_of",
    "published_value", "rows_html", "select", "status_changes", "summary", "thesis_chapter",
    "update_expected_status", "validate_report", "write_rows",
]
