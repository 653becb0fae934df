"""Report rows: the :class:`Row` of one claim, the CSV parts the rules write, the joined report,
and how the book groups and picks rows (by thesis chapter, by claim id)."""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import pandas as pd

from .statuses import STATUSES

__all__ = [
    "COLUMNS", "Row", "write_rows", "combine", "summary", "CHAPTERS", "thesis_chapter",
    "figure_ids", "figure_coverage", "load", "select", "by_id", "book_pages",
]

COLUMNS: tuple[str, ...] = (
    "id", "item", "section", "published", "reproduced", "tolerance", "status", "note",
)


@dataclass
class Row:
    """One line of the reproduction report.

    ``published`` and ``reproduced`` are strings so that ranges ("0.1-5 %") and numbers sit in one
    column; ``tolerance`` says how the two were compared; ``note`` explains a difference; ``id``
    is the claim's id (``data/published/claims.yaml``) with its fields filled in (the first
    column of the report; :func:`check` sets it).
    """

    item: str
    section: str
    published: str
    reproduced: str
    tolerance: str
    status: str
    note: str = ""
    id: str = ""

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status {self.status!r} not in {STATUSES}")


def write_rows(rows: Iterable[Row], path: str | Path) -> pd.DataFrame:
    """Write report rows to ``path`` (CSV with :data:`COLUMNS`) and return them as a DataFrame."""
    df = pd.DataFrame([asdict(r) for r in rows], columns=list(COLUMNS))
    if df.empty:
        raise ValueError(f"no report rows for {path}")
    _check_ids(df, str(path))
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False)
    return df


def combine(parts: Sequence[str | Path], out: str | Path) -> pd.DataFrame:
    """Join report parts into the reproduction report, checking columns and statuses."""
    frames = [pd.DataFrame(columns=list(COLUMNS))]
    for part in parts:
        df = pd.read_csv(part, dtype=str, keep_default_na=False)
        if list(df.columns) != list(COLUMNS):
            raise ValueError(f"{part}: columns {list(df.columns)} != {list(COLUMNS)}")
        bad = set(df["status"]) - set(STATUSES)
        if bad:
            raise ValueError(f"{part}: unknown status {sorted(bad)}")
        frames.append(df)
    report = pd.concat(frames, ignore_index=True)
    if report.isna().any().any():
        raise ValueError("reproduction report has missing cells")
    _check_ids(report, "reproduction report")
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    report.to_csv(out, index=False)
    return report


def _check_ids(df: pd.DataFrame, where: str) -> None:
    """Every row has an id (from :func:`check`) and no id repeats."""
    empty = df["id"].astype(str).str.strip() == ""
    if empty.any():
        raise ValueError(f"{where}: rows without a claim id: {list(df.loc[empty, 'item'])[:3]}")
    dup = df["id"][df["id"].duplicated()]
    if not dup.empty:
        raise ValueError(f"{where}: repeated claim ids {sorted(set(dup))[:5]}")


def summary(report: pd.DataFrame) -> dict[str, int]:
    """Count of rows per status (every status present, zeros included)."""
    counts = report["status"].value_counts()
    return {s: int(counts.get(s, 0)) for s in STATUSES}


#: Thesis chapters in book order (the report and the book group rows by these).
CHAPTERS: dict[str, str] = {
    "2": "2 Pedalling disturbance",
    "3": "3 Open-loop response",
    "4": "4 Closed loop and validation",
    "5": "5 Conclusions",
    "appendix": "Appendices",
    "other": "Other",
}


def thesis_chapter(section: str) -> str:
    """Key of :data:`CHAPTERS` for a report row's ``section`` string.

    ``"2.2.1"``, ``"3.2.4 1a"``, ``"Fig 3.12"`` -> the leading chapter digit; ``"Appendix B"``,
    ``"Table D.1"``, ``"B.3"``, ``"Fig G.7"`` -> ``"appendix"``; anything else -> ``"other"``.

    Examples
    --------
    >>> thesis_chapter("2.2.1"), thesis_chapter("Table D.1"), thesis_chapter("Table 4.1")
    ('2', 'appendix', '4')
    """
    text = str(section).strip()
    if re.match(r"(?i)^appendix\b", text):
        return "appendix"
    text = re.sub(r"(?i)^(sec(tion)?|table|fig(ure)?|eq(uation)?)\.?\s*", "", text)
    m = re.match(r"([0-9]+|[A-H])(?:\.[0-9]+)*\b", text)
    if m is None:
        return "other"
    head = m.group(1)
    if head.isalpha():
        return "appendix"
    return head if head in CHAPTERS else "other"


def figure_ids() -> pd.DataFrame:
    """The thesis figure and table ids the book should show (``data/figure_ids.yaml``, copied from
    the project's reproduction checklist), in thesis order: columns id, thesis, chapter, what."""
    import yaml

    from .. import paths

    with open(paths.DATA / "figure_ids.yaml", encoding="utf-8") as f:
        ids = yaml.safe_load(f)["ids"]
    return pd.DataFrame(ids, columns=["id", "thesis", "chapter", "what"]).astype(str)


def figure_coverage(root: str | Path | None = None) -> pd.DataFrame:
    """Which ids of :func:`figure_ids` the pipeline has produced (``results/figures/<id>.png`` or
    ``results/tables/<id>.csv`` exists): the id table plus a boolean column ``present``.
    ``root``: another results folder."""
    from .. import paths

    ids = figure_ids()
    ids["present"] = [
        (paths.table(i, root) if i.startswith("table_") else paths.figure(i, root)).exists()
        for i in ids["id"]
    ]
    return ids


def load() -> pd.DataFrame:
    """The joined reproduction report (``results/tables/reproduction_report.csv``), all strings."""
    from .. import paths

    return pd.read_csv(paths.table("reproduction_report"), dtype=str, keep_default_na=False)


def select(report: pd.DataFrame, section: str = "", *words: str) -> pd.DataFrame:
    """Rows whose ``section`` starts with ``section`` and whose item contains every word
    (case-insensitive); how the book's text points at report rows without retyping values.

    Examples
    --------
    >>> df = pd.DataFrame([Row("NRMSD vertical COM", "2.2.1", "3.6", "3.57", "abs 0.05",
    ...                        "reproduced").__dict__])
    >>> len(select(df, "2.2", "vertical")), len(select(df, "3"))
    (1, 0)
    """
    keep = report["section"].str.strip().str.startswith(section)
    for word in words:
        keep &= report["item"].str.contains(word, case=False, regex=False)
    return report[keep]


def by_id(report: pd.DataFrame, *ids: str) -> pd.DataFrame:
    """Rows of ``report`` by claim id, in the order asked; an id ending in ``.`` or ``*`` selects
    every row whose id starts with it (``by_id(rep, "table_d_1.")``). KeyError if one matches
    nothing, so a notebook cannot silently show an empty table.

    Examples
    --------
    >>> df = pd.DataFrame({"id": ["a.x", "a.y", "b"], "status": ["reproduced"] * 3})
    >>> list(by_id(df, "b", "a.")["id"])
    ['b', 'a.x', 'a.y']
    """
    parts = []
    for wanted in ids:
        if wanted.endswith((".", "*")):
            hit = report[report["id"].str.startswith(wanted.rstrip("*"))]
        else:
            hit = report[report["id"] == wanted]
        if hit.empty:
            raise KeyError(f"no report row with id {wanted!r}")
        parts.append(hit)
    return pd.concat(parts) if parts else report.iloc[:0]


def book_pages(toc_path: str | Path | None = None) -> list[str]:
    """Every document of the book's ``_toc.yml`` (the root first, then in reading order), as paths
    relative to ``book/`` without suffix (``"notebooks/reproduction_report"``)."""
    import yaml

    from .. import paths

    toc = yaml.safe_load(Path(toc_path or paths.BOOK / "_toc.yml").read_text(encoding="utf-8"))
    docs = [toc["root"]]

    def walk(entries) -> None:
        for entry in entries or []:
            if "file" in entry:
                docs.append(str(entry["file"]))
            walk(entry.get("sections"))
            walk(entry.get("chapters"))

    for part in toc.get("parts", []):
        walk(part.get("chapters"))
    walk(toc.get("chapters"))
    return docs


