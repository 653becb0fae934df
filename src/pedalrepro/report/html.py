"""HTML of report rows for the book: the status coloured, a note under its row, an anchor per
claim id so that other pages link to it."""

from __future__ import annotations

import re

import pandas as pd

from .rows import COLUMNS, summary
from .statuses import (
    CALIBRATED,
    CONSISTENT,
    DIFFERS,
    MEANING,
    NOT_REPRODUCIBLE,
    REPRODUCED,
    STATUSES,
)

__all__ = ["REPORT_PAGE", "anchor", "status_span", "rows_html", "links_html", "legend_html"]

#: The report page, relative to the book's root (conclusions and deviations link rows on it).
REPORT_PAGE = "notebooks/reproduction_report.html"
_COLOURS = {REPRODUCED: "#2e7d32", CONSISTENT: "#1565c0", CALIBRATED: "#8d6e00",
            DIFFERS: "#c62828", NOT_REPRODUCIBLE: "#6d6d6d"}


def anchor(claim_id: str) -> str:
    """The HTML id of a report row on the report page (``report-`` + the claim id, with every
    character other than letters, digits, ``-`` and ``_`` replaced by ``-``).

    Examples
    --------
    >>> anchor("table_4_1.measured.roll.CR_25")
    'report-table_4_1-measured-roll-CR_25'
    """
    return "report-" + re.sub(r"[^A-Za-z0-9_-]", "-", str(claim_id))


def status_span(status: str) -> str:
    """A status as the book shows it: ``<span>`` in the status's colour, bold (the report page,
    the figure captions' status lines).

    Examples
    --------
    >>> status_span("differs")
    '<span style="color:#c62828;font-weight:bold">differs</span>'
    """
    import html

    return (f'<span style="color:{_COLOURS.get(status, "#000")};font-weight:bold">'
            f"{html.escape(status)}</span>")


def rows_html(rows: pd.DataFrame, empty: str = "No report row yet.") -> str:
    """HTML table of report rows with the status coloured (for notebooks and book pages).

    Each row's note, when there is one, is a full-width line under it (wrapped, never cut off by
    the column), and each row carries the anchor :func:`anchor` of its claim id so other pages can
    link to it (:func:`links_html`)."""
    if rows.empty:
        return f"<p><em>{empty}</em></p>"
    import html

    cols = [c for c in COLUMNS if c not in ("id", "note")]
    head = "".join(f"<th>{c}</th>" for c in cols)
    body = []
    for r in rows.astype(str).to_dict("records"):
        cells = "".join(
            f"<td>{status_span(r[c]) if c == 'status' else html.escape(r[c])}</td>"
            for c in cols)
        rid = f' id="{anchor(r["id"])}"' if r.get("id") else ""
        body.append(f"<tr{rid}>{cells}</tr>")
        if r.get("note"):
            body.append(f'<tr class="pedalrepro-note"><td colspan="{len(cols)}" '
                        'style="white-space:normal;border-top:none;padding-top:0">'
                        f"<small><em>note:</em> {html.escape(r['note'])}</small></td></tr>")
    table = (f'<table class="table pedalrepro-report"><thead><tr>{head}</tr></thead>'
             f"<tbody>{''.join(body)}</tbody></table>")
    return f'<div style="overflow-x:auto">{table}</div>'


def links_html(rows: pd.DataFrame, page: str = REPORT_PAGE,
               empty: str = "No report row yet.") -> str:
    """A short paragraph that points at report rows instead of re-printing them: the count per
    status, then a link to each row that is not reproduced (the findings), by item and claim id.

    ``page``: the report page relative to the page that shows the paragraph (the book's root
    pages use the default)."""
    if rows.empty:
        return f"<p><em>{empty}</em></p>"
    import html

    counts = summary(rows)
    text = (f"<p><strong>Report rows ({len(rows)}):</strong> "
            + ", ".join(f"{n} {status_span(s)}" for s, n in counts.items() if n) + ".")
    findings = rows[rows["status"].isin([DIFFERS, NOT_REPRODUCIBLE])]
    if not findings.empty:
        text += " Differ or not reproducible here: " + "; ".join(
            f'<a href="{page}#{anchor(r["id"])}">{html.escape(r["item"])}</a> '
            f'(<code>{html.escape(r["id"])}</code>, {html.escape(r["status"])})'
            for r in findings.astype(str).to_dict("records")) + "."
    return text + "</p>"




def legend_html() -> str:
    """The five statuses with their meaning (:data:`~pedalrepro.report.statuses.MEANING`), as an
    HTML list for the report page."""
    import html

    items = "".join(f"<li>{status_span(s)}: {html.escape(MEANING[s])}.</li>" for s in STATUSES)
    return f'<ul class="pedalrepro-legend">{items}</ul>'
