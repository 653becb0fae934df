"""The reproduction report: every published number beside the project's value, with a status.

Each published claim has an id and a check in ``data/published/claims.yaml`` (the published
value itself is referenced in ``thesis_values.yaml`` or ``meijaard2007.yaml``, or given as text
for a qualitative claim). :func:`check` turns a claim and the pipeline's value into a report
:class:`Row`; it is the only place where a status is decided. Each part of the pipeline writes its
rows to ``results/tables/report/<part>.csv`` with :func:`write_rows`; the ``report`` rule joins
them into ``results/tables/reproduction_report.csv`` with :func:`combine`. Notebooks pick rows by
id with :func:`by_id`. Reproduced values are computed by the pipeline, never typed in.

Check kinds (``check: {kind: ...}`` in ``claims.yaml``), ``p`` the published value, ``x`` the
reproduced one:

``abs``                 ``|x - p| <= tol``
``relative``            ``|x - p| <= tol |p|``
``rounds_to``           ``|x - p| <= 0.5 10^-decimals`` (``p`` printed with ``decimals`` decimals)
``half_step``           ``|x - p| <= step / 2 + 1e-9`` (``step``: the caller's grid step)
``range``               ``lo <= x <= hi`` (``p = [lo, hi]``, or ``p`` alone: ``0 <= x <= p``)
``order_of_magnitude``  ``p / factor <= x <= p factor`` (``factor`` default 10)
``below`` / ``above``   ``x < limit`` / ``x > limit`` (``limit`` default ``p``)
``at_most``             ``x <= limit``
``equals``              ``x == p`` (text or number)
``holds``               ``x`` is a boolean worked out by the caller (a qualitative claim)
``not_reproducible``    always ``not reproducible here`` (the thesis's means are not available)
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

COLUMNS: tuple[str, ...] = (
    "id", "item", "section", "published", "reproduced", "tolerance", "status", "note",
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


#: Data files this module reads by a computed name (pedalrepro.dependencies picks them up as rule
#: inputs): the claims and the published values they reference.
DATA_FILES: tuple[str, ...] = ("data/published/claims.yaml", "data/published/thesis_values.yaml",
                               "data/published/meijaard2007.yaml")

#: Check kinds of ``data/published/claims.yaml`` and the parameter each needs.
CHECK_KINDS: dict[str, tuple[str, ...]] = {
    "abs": ("tol",), "relative": ("tol",), "rounds_to": ("decimals",), "half_step": (),
    "range": (), "order_of_magnitude": (), "below": (), "above": (), "at_most": (),
    "equals": (), "holds": ("describe",), "not_reproducible": (),
}
_CLAIM_KEYS = {"id", "section", "item", "value", "published_text", "check", "fmt", "unit"}


@dataclass(frozen=True)
class Claim:
    """A published claim and how the report checks it (one entry of ``claims.yaml``).

    ``id``, ``item``, ``section``, ``value`` and ``published_text`` are templates: ``{field}``
    is filled from the keyword fields given to :func:`check` (e.g. ``model``, ``coord``), so one
    entry covers e.g. the eight rows "RD 2b <model> <coord>". ``value`` references the published
    number as ``"<file in data/published>:<key>/<key>/..."`` (a list is indexed by position or, for
    a list of mappings, by their ``id``).
    """

    id: str
    section: str
    item: str
    check: Mapping[str, Any]
    value: str | None = None
    published_text: str | None = None
    fmt: str = "{:.6g}"
    unit: str = ""
    source: str = field(default="", compare=False)

    @property
    def kind(self) -> str:
        return str(self.check["kind"])


def _claims_file() -> Path:
    from . import paths

    return paths.PUBLISHED / "claims.yaml"


@lru_cache(maxsize=4)
def _load_claims(path: str) -> dict[str, Claim]:
    from .params import read_yaml

    data = read_yaml(path)
    out: dict[str, Claim] = {}
    for i, entry in enumerate(data.get("claims") or []):
        where = f"{path}: claims[{i}]"
        if not isinstance(entry, dict) or "id" not in entry:
            raise ValueError(f"{where}: every claim needs an 'id'")
        where = f"{path}: claim {entry['id']!r}"
        unknown = set(entry) - _CLAIM_KEYS
        missing = {"section", "item", "check"} - set(entry)
        if unknown or missing:
            raise ValueError(f"{where}: unknown keys {sorted(unknown)}, missing {sorted(missing)}")
        chk = entry["check"]
        kind = chk.get("kind") if isinstance(chk, dict) else None
        if kind not in CHECK_KINDS:
            raise ValueError(f"{where}: check kind {kind!r} not in {sorted(CHECK_KINDS)}")
        need = [k for k in CHECK_KINDS[kind] if k not in chk]
        if need:
            raise ValueError(f"{where}: check kind {kind!r} needs {need}")
        if entry.get("value") is None and entry.get("published_text") is None:
            raise ValueError(f"{where}: needs a published 'value' reference or 'published_text'")
        if entry["id"] in out:
            raise ValueError(f"{where}: duplicate id")
        out[entry["id"]] = Claim(**{k: v for k, v in entry.items()}, source=path)
    return out


def claims(path: str | Path | None = None) -> dict[str, Claim]:
    """Every claim of ``data/published/claims.yaml`` (or ``path``) by id template."""
    return _load_claims(str(path or _claims_file()))


def claim(claim_id: str, path: str | Path | None = None) -> Claim:
    """One claim by its id template (e.g. ``"rd_2b.{model}.{coord}"``); KeyError names the file."""
    found = claims(path)
    if claim_id not in found:
        raise KeyError(f"claim {claim_id!r} not in {path or _claims_file()}")
    return found[claim_id]


def published_value(reference: str, **fields: Any) -> Any:
    """The published value a reference ``"<file>:<key>/<key>/..."`` points at (fields filled).

    Examples
    --------
    >>> published_value("meijaard2007.yaml:weave_speed_m_s")
    4.292382785185271
    """
    from . import paths
    from .params import read_yaml

    file, _, keys = reference.format(**fields).partition(":")
    node: Any = read_yaml(paths.PUBLISHED / file)
    walked = file
    for key in [k for k in keys.split("/") if k]:
        walked += f"/{key}"
        if isinstance(node, list) and all(isinstance(x, dict) and "id" in x for x in node):
            hit = [x for x in node if x["id"] == key]
            node = hit[0] if len(hit) == 1 else None
        elif isinstance(node, list):
            node = node[int(key)] if key.lstrip("-").isdigit() and -len(node) <= int(key) < len(
                node) else None
        elif isinstance(node, dict):
            node = node.get(key, node.get(int(key)) if key.isdigit() else None)
        else:
            node = None
        if node is None:
            raise KeyError(f"published value {walked!r} not found (data/published/{file})")
    return node


def _fill(template: str, fields: Mapping[str, Any], what: str, claim_id: str) -> str:
    try:
        return template.format(**fields)
    except (KeyError, IndexError) as exc:
        raise KeyError(f"claim {claim_id!r}: {what} needs field {exc}") from None


def check(
    claim_or_id: Claim | str,
    value: Any,
    *,
    shown: str | None = None,
    label: str = "",
    note: str = "",
    step: float | None = None,
    unavailable: str | None = None,
    **fields: Any,
) -> Row:
    """The report row of a published claim and the pipeline's value: the one place a status is
    decided (check kinds: module docstring).

    Parameters
    ----------
    claim_or_id
        A :class:`Claim` or its id template in ``data/published/claims.yaml``.
    value
        The reproduced value (a finite number; a bool for ``holds``; text or number for
        ``equals``; ignored for ``not_reproducible``; may be None with ``unavailable``).
    shown
        Text of the ``reproduced`` column (default: ``value`` in the claim's ``fmt``).
    label
        Appended to the reproduced text (e.g. ``" (synthetic)"``).
    note
        The row's note (why it differs, how the value was obtained).
    step
        Grid step for ``half_step``.
    unavailable
        If given, the status is ``not reproducible here`` whatever the value, and this reason is
        the note unless ``note`` is given.
    **fields
        Fill the claim's templates (``{model}``, ``{coord}``, ...).
    """
    c = claim_or_id if isinstance(claim_or_id, Claim) else claim(claim_or_id)
    fields = dict(fields)
    rid = _fill(c.id, fields, "id", c.id)
    pub = published_value(c.value, **fields) if c.value is not None else None
    chk = dict(c.check)
    kind = c.kind
    unit = f" {c.unit}" if c.unit else ""

    def num(x: Any, what: str) -> float:
        try:
            out = float(x)
        except (TypeError, ValueError):
            raise ValueError(f"report item {rid!r}: {what} {x!r} is not a number") from None
        if not np.isfinite(out):
            raise ValueError(f"report item {rid!r}: {what} is not finite ({x})")
        return out

    def limit() -> float:
        return num(chk["limit"] if "limit" in chk else pub, "limit")

    text_fields = dict(fields, value=pub)
    if kind == "range" and pub is not None:
        lo, hi = (pub if isinstance(pub, list) else (0.0, pub))
        text_fields.update(lo=lo, hi=hi)
    if c.published_text is not None:
        published = _fill(c.published_text, text_fields, "published_text", c.id)
    elif kind == "range":
        published = (f"{lo:g}-{hi:g}{unit}" if isinstance(pub, list) else f"up to {hi:g}{unit}")
    elif kind == "order_of_magnitude":
        published = f"~{pub:g}{unit}"
    elif kind in ("below", "above", "at_most"):
        published = {"below": "< ", "above": "> ", "at_most": "<= "}[kind] + f"{limit():g}{unit}"
    else:
        published = c.fmt.format(pub)

    # the tolerance text and the bound, from the check alone
    bound = 0.0
    if kind == "relative":
        tol = f"rel {float(chk['tol']):g}"
    elif kind in ("abs", "rounds_to", "half_step"):
        if kind == "abs":
            bound = float(chk["tol"])
        elif kind == "rounds_to":
            bound = 0.5 * 10.0 ** -int(chk["decimals"])
        elif step is not None:
            bound = step / 2 + 1e-9
        elif unavailable is None:
            raise ValueError(f"report item {rid!r}: half_step needs step=")
        tol = f"abs {bound:g}"
    elif kind == "range":
        tol = "inside the published range"
    elif kind == "order_of_magnitude":
        f = float(chk.get("factor", 10))
        tol = f"same order of magnitude (x/{f:g} .. x{f:g})"
    elif kind in ("below", "above", "at_most"):
        tol = kind.replace("_", " ")
    elif kind == "equals":
        tol = "exact"
    else:  # holds, not_reproducible: `describe` says what was checked
        tol = ""

    ok = False
    if unavailable is not None or kind == "not_reproducible":
        if value is None and shown is None:
            shown = "n/a"
    elif kind in ("abs", "relative", "rounds_to", "half_step"):
        x, p = num(value, "reproduced value"), num(pub, "published value")
        if kind == "relative":
            bound = float(chk["tol"]) * abs(p)
        ok = abs(x - p) <= bound
    elif kind == "range":
        x = num(value, "reproduced value")
        ok = num(lo, "lower bound") <= x <= num(hi, "upper bound")
    elif kind == "order_of_magnitude":
        x, p = num(value, "reproduced value"), num(pub, "published value")
        ok = p / f <= x <= p * f
    elif kind in ("below", "above", "at_most"):
        x, lim = num(value, "reproduced value"), limit()
        ok = {"below": x < lim, "above": x > lim, "at_most": x <= lim}[kind]
    elif kind == "equals":
        ok = value == (pub if pub is not None else published)
    else:  # holds
        if not isinstance(value, bool | np.bool_):
            raise ValueError(f"report item {rid!r}: 'holds' needs a bool, got {value!r}")
        ok = bool(value)
    tol = chk.get("describe", tol)
    if shown is None:
        numeric = isinstance(value, int | float | np.number) and not isinstance(value, bool)
        shown = c.fmt.format(value) if numeric else str(value)
    if unavailable is not None or kind == "not_reproducible":
        status = NOT_REPRODUCIBLE
        note = note or (unavailable or "")
    else:
        status = REPRODUCED if ok else DIFFERS
    return Row(_fill(c.item, text_fields, "item", c.id), _fill(c.section, fields, "section", c.id),
               published, shown + label, tol, status, note, id=rid)


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

    from . import paths

    with open(paths.DATA / "figure_ids.yaml", encoding="utf-8") as f:
        ids = yaml.safe_load(f)["ids"]
    return pd.DataFrame(ids, columns=["id", "thesis", "chapter", "what"]).astype(str)


def figure_coverage(root: str | Path | None = None) -> pd.DataFrame:
    """Which ids of :func:`figure_ids` the pipeline has produced (``results/figures/<id>.png`` or
    ``results/tables/<id>.csv`` exists): the id table plus a boolean column ``present``.
    ``root``: another results folder."""
    from . import paths

    ids = figure_ids()
    ids["present"] = [
        (paths.table(i, root) if i.startswith("table_") else paths.figure(i, root)).exists()
        for i in ids["id"]
    ]
    return ids


def load() -> pd.DataFrame:
    """The joined reproduction report (``results/tables/reproduction_report.csv``), all strings."""
    from . import paths

    return pd.read_csv(paths.table("reproduction_report"), dtype=str, keep_default_na=False)


def select(report: pd.DataFrame, section: str = "", *words: str) -> pd.DataFrame:
    """Rows whose ``section`` starts with ``section`` and whose item contains every word
    (case-insensitive); how the book's text points at report rows without retyping values.

    Examples
    --------
    >>> df = pd.DataFrame([Row("NRMSD vertical COM", "2.2.1", "3.6", "3.57", "abs 0.05",
    ...                        REPRODUCED).__dict__])
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


#: The report page, relative to the book's root (conclusions and deviations link rows on it).
REPORT_PAGE = "notebooks/reproduction_report.html"
_COLOURS = {REPRODUCED: "#2e7d32", DIFFERS: "#c62828", NOT_REPRODUCIBLE: "#6d6d6d"}


def anchor(claim_id: str) -> str:
    """The HTML id of a report row on the report page (``report-`` + the claim id, with every
    character other than letters, digits, ``-`` and ``_`` replaced by ``-``).

    Examples
    --------
    >>> anchor("table_4_1.measured.roll.CR_25")
    'report-table_4_1-measured-roll-CR_25'
    """
    return "report-" + re.sub(r"[^A-Za-z0-9_-]", "-", str(claim_id))


def _status_html(status: str) -> str:
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
            f"<td>{_status_html(r[c]) if c == 'status' else html.escape(r[c])}</td>"
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
            + ", ".join(f"{n} {_status_html(s)}" for s, n in counts.items() if n) + ".")
    findings = rows[rows["status"] != REPRODUCED]
    if not findings.empty:
        text += " Not reproduced: " + "; ".join(
            f'<a href="{page}#{anchor(r["id"])}">{html.escape(r["item"])}</a> '
            f'(<code>{html.escape(r["id"])}</code>, {html.escape(r["status"])})'
            for r in findings.astype(str).to_dict("records")) + "."
    return text + "</p>"


def book_pages(toc_path: str | Path | None = None) -> list[str]:
    """Every document of the book's ``_toc.yml`` (the root first, then in reading order), as paths
    relative to ``book/`` without suffix (``"notebooks/reproduction_report"``)."""
    import yaml

    from . import paths

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


# --- Pinned statuses --------------------------------------------------------------------------
#: Where the expected status of every report row is pinned, per profile (a test expectation).
EXPECTED_STATUS_FILE = "tests/expected_status.csv"
#: The profiles with a column in the expected-status file (``profile`` in ``config/*.yaml``).
PROFILES: tuple[str, ...] = ("quick", "thesis")


def expected_status(path: str | Path | None = None) -> pd.DataFrame:
    """The pinned statuses: columns ``id`` and one per :data:`PROFILES` ("" = not recorded)."""
    from . import paths

    path = Path(path or paths.ROOT / EXPECTED_STATUS_FILE)
    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    if list(df.columns) != ["id", *PROFILES]:
        raise ValueError(f"{path}: columns {list(df.columns)} != {['id', *PROFILES]}")
    bad = set(df[list(PROFILES)].to_numpy().ravel()) - {"", *STATUSES}
    if bad:
        raise ValueError(f"{path}: unknown status {sorted(bad)}")
    if df["id"].duplicated().any():
        raise ValueError(f"{path}: repeated ids {sorted(set(df['id'][df['id'].duplicated()]))}")
    return df


def status_changes(rep: pd.DataFrame, expected: pd.DataFrame, profile: str) -> pd.DataFrame:
    """Rows whose status differs from the pinned one of ``profile``, and rows added or removed:
    columns id, expected, got ("" for a row that is absent on that side)."""
    if profile not in PROFILES:
        raise ValueError(f"profile {profile!r} not in {PROFILES}")
    want = dict(zip(expected["id"], expected[profile], strict=True))
    want = {k: v for k, v in want.items() if v}
    got = dict(zip(rep["id"], rep["status"], strict=True))
    ids = list(got) + [k for k in want if k not in got]
    out = [(i, want.get(i, ""), got.get(i, "")) for i in ids if want.get(i, "") != got.get(i, "")]
    return pd.DataFrame(out, columns=["id", "expected", "got"])


def update_expected_status(rep: pd.DataFrame, profile: str, path: str | Path | None = None
                           ) -> pd.DataFrame:
    """Record the statuses of ``rep`` as the pinned ones of ``profile`` (other profiles kept;
    ids of the report first, in report order), write the file and return it."""
    from . import paths

    path = Path(path or paths.ROOT / EXPECTED_STATUS_FILE)
    old = (expected_status(path) if path.exists()
           else pd.DataFrame(columns=["id", *PROFILES], dtype=str))
    ids = list(rep["id"]) + [i for i in old["id"] if i not in set(rep["id"])]
    new = pd.DataFrame({"id": ids}).merge(old, on="id", how="left").fillna("")
    new[profile] = new["id"].map(dict(zip(rep["id"], rep["status"], strict=True))).fillna("")
    keep = (new[list(PROFILES)] != "").any(axis=1)
    new = new[keep][["id", *PROFILES]]
    new.to_csv(path, index=False)
    return new


def add_cli(sub) -> None:
    """``pedalrepro report-status``: compare a reproduction report with the pinned statuses."""
    p = sub.add_parser(
        "report-status",
        help="compare a reproduction report's statuses with tests/expected_status.csv",
        description="Compare (or with --update record) the status of every report row against "
                    f"{EXPECTED_STATUS_FILE} for one profile.")
    p.add_argument("report", help="results/<...>/tables/reproduction_report.csv")
    p.add_argument("--profile", required=True, choices=PROFILES)
    p.add_argument("--update", action="store_true",
                   help="write the report's statuses into the file (then commit it with the "
                        "reason for every change in the message)")
    p.set_defaults(func=_cli_status)


def _cli_status(args) -> int:
    from . import paths

    rep = pd.read_csv(args.report, dtype=str, keep_default_na=False)
    pinned = (expected_status() if (paths.ROOT / EXPECTED_STATUS_FILE).exists()
              else pd.DataFrame(columns=["id", *PROFILES], dtype=str))
    changes = status_changes(rep, pinned, args.profile)
    print(changes.to_string(index=False) if len(changes) else "no status change")
    if args.update:
        update_expected_status(rep, args.profile)
        print(f"updated {EXPECTED_STATUS_FILE} ({args.profile})")
        return 0
    return 1 if len(changes) else 0
