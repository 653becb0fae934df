"""Which report rows check which thesis figure, and the status line each figure shows in the book.

A claim of ``data/published/claims.yaml`` names the figures and tables it is read from or checks
(its ``figures`` key: registry ids or registry selectors, templates filled from the row's id). A
report row belongs to the claim whose id template matches its id (the most specific template:
``table_4_2.spectra.{key}.CF`` before ``table_4_2.{key}.{system}``); its figures are that claim's,
filled with the fields the id carries. :func:`status_html` is the line under a figure's caption:
the count of its rows per status, linked to the report page, or, for a figure no row checks, that
it is compared with the thesis's by eye only.

Not imported by the package ``pedalrepro.report`` (whose rule scripts must not depend on the
figure drawing code this module reaches through the figure registry): the notebooks import it
as ``from pedalrepro.report import figure_rows``.
"""

from __future__ import annotations

import html
import re
from collections.abc import Mapping
from functools import lru_cache
from typing import Any

import pandas as pd

from .claims import Claim, claims
from .html import anchor, status_span
from .rows import summary

_FIELD = re.compile(r"\{([^}]*)\}")


def _pattern(template: str) -> re.Pattern[str]:
    parts = _FIELD.split(template)
    rx = "".join(re.escape(p) if k % 2 == 0 else f"(?P<{p}>.+?)" for k, p in enumerate(parts))
    return re.compile(rx + r"\Z")


@lru_cache(maxsize=4)
def _patterns(path: str | None) -> tuple[tuple[Claim, re.Pattern[str], int], ...]:
    return tuple((c, _pattern(t), len(_FIELD.sub("", t))) for t, c in claims(path).items())


def match(row_id: str, path: str | None = None) -> tuple[Claim, dict[str, str]]:
    """The claim a report row belongs to and the template fields its id carries.

    The most specific matching id template wins (the most literal text); a row id that matches
    no claim, or two equally specific ones, is a ValueError naming it.

    Examples
    --------
    >>> c, fields = match("rd_2b.HS.roll")
    >>> c.id, fields
    ('rd_2b.{model}.{coord}', {'model': 'HS', 'coord': 'roll'})
    """
    hits = [(c, m.groupdict(), n) for c, rx, n in _patterns(path) if (m := rx.match(row_id))]
    if not hits:
        raise ValueError(f"report row {row_id!r} matches no claim of claims.yaml")
    best = max(n for _, _, n in hits)
    hits = [(c, f) for c, f, n in hits if n == best]
    if len(hits) > 1:
        raise ValueError(f"report row {row_id!r} matches {[c.id for c, _ in hits]} equally")
    return hits[0]


def _resolve(ref: Any, fields: Mapping[str, str], claim_id: str) -> list[str]:
    from ..figures import registry

    def fill(text: str) -> str:
        try:
            return str(text).format(**fields)
        except (KeyError, IndexError) as err:
            raise ValueError(f"claim {claim_id!r}: figures entry {ref!r} needs {err}") from None

    known = set(registry.ids()) | {"table_4_1", "table_4_2", "table_d_1"}
    if isinstance(ref, str):
        fid = fill(ref)
        if fid not in known:
            raise ValueError(f"claim {claim_id!r}: figure {fid!r} is not a registered figure or "
                             "thesis table")
        return [fid]
    want = {k: fill(v) for k, v in ref.items() if k != "function"}
    found = [fid for fid in registry.ids()
             if registry.spec(fid).function == ref["function"]
             and all(str(registry.spec(fid).kwargs.get(k)) == v for k, v in want.items())]
    if not found:
        raise ValueError(f"claim {claim_id!r}: no registered figure is drawn by {ref!r} "
                         f"with {want}")
    return found


def figures_of(row_id: str, path: str | None = None) -> list[str]:
    """The figure and table ids report row ``row_id`` is read from or checks (its claim's
    ``figures``, filled), in the claim's order; [] for a claim that names none (a number stated
    in the text only)."""
    c, fields = match(row_id, path)
    out: list[str] = []
    for ref in c.figures:
        out += [f for f in _resolve(ref, fields, c.id) if f not in out]
    return out


def by_figure(report: pd.DataFrame, path: str | None = None) -> dict[str, pd.DataFrame]:
    """Figure id -> the report rows checking it (the rows in report order)."""
    rows: dict[str, list[int]] = {}
    for i, rid in enumerate(report["id"]):
        for fid in figures_of(str(rid), path):
            rows.setdefault(fid, []).append(i)
    return {fid: report.iloc[idx] for fid, idx in rows.items()}


#: The line a figure no report row checks shows.
BY_EYE = "no report row checks this figure: compare it with the thesis figure by eye"


def status_html(rows: pd.DataFrame, page: str = "reproduction_report.html") -> str:
    """The report-status line under a figure's caption (``<span class="pedalrepro-status">``)
    for the report rows checking it (:func:`by_figure`): "report rows (4): 3 reproduced,
    1 differs", each status linking the first of its rows on the report page; :data:`BY_EYE`
    when there are none.

    ``page``: the report page relative to the page showing the figure (the notebooks' pages sit
    beside it, in ``notebooks/``)."""
    if rows.empty:
        text = html.escape(BY_EYE)
    else:
        parts = []
        for status, n in summary(rows).items():
            if n:
                first = rows[rows["status"] == status]["id"].iloc[0]
                parts.append(f'<a href="{page}#{anchor(first)}">{n} {status_span(status)}</a>')
        text = f"report rows ({len(rows)}): " + ", ".join(parts)
    return f' <span class="pedalrepro-status">{text}.</span>'


def caption_status(report: pd.DataFrame | None = None, page: str = "reproduction_report.html"):
    """A function figure id -> :func:`status_html` of its rows in ``report`` (default: the
    build's joined report), for :func:`pedalrepro.book.setup` (``figure_status=``): every figure
    a notebook then shows carries its status line (a figure beyond the thesis that no row
    checks: none). The book module never imports the report (so
    editing a claim reruns no figure rule); the notebook hands this function to it."""
    from ..book import BEYOND_THESIS, thesis_label
    from .rows import load

    rep = load() if report is None else report
    table = by_figure(rep)

    def status(figure_id: str) -> str:
        rows = table.get(figure_id, rep.iloc[:0])
        if rows.empty and thesis_label(figure_id) == BEYOND_THESIS:
            return ""  # not a thesis figure: nothing of the thesis's to compare by eye
        return status_html(rows, page)

    return status


__all__ = ["BY_EYE", "by_figure", "caption_status", "figures_of", "match",
           "status_html"]
