"""Published claims and their checks: ``data/published/claims.yaml`` and :func:`check`.

Each claim has an id and a check; the published value itself is referenced in
``thesis_values.yaml`` or ``meijaard2007.yaml``, or given as text for a qualitative claim, and
``wording`` quotes the thesis sentence its kind and tolerance come from. :func:`check` turns a
claim and the pipeline's value into a report :class:`~pedalrepro.report.rows.Row`; it is the only
place where a status is decided (:mod:`pedalrepro.report.statuses` defines the five).

Check kinds (``check: {kind: ...}``), ``p`` the published value, ``x`` the reproduced one; each
is one :class:`Kind` in :data:`KINDS`. Precise kinds (a pass is ``reproduced``):

- ``rounds_to``: ``|x - p| <= 0.5 10^-decimals`` (the printed precision);
- ``abs``: ``|x - p| <= tol``, precise if ``tol <= 10 % |p|``;
- ``relative``: ``|x - p| <= tol |p|``, precise if ``tol <= 10 %``;
- ``half_step``: ``|x - p| <= step / 2 + 1e-9`` (the caller's grid), precise if ``<= 10 % |p|``;
- ``max_difference``: ``x <= limit``, ``x`` the largest difference of a set of reproduced numbers
  from the published ones (``describe`` says how it is measured), precise if ``limit <= 10 %``;
- ``equals``: ``x == p``, precise for a number (text is a statement in words).

Loose kinds (a pass is only ``consistent``):

- ``range``: ``lo <= x <= hi`` (``p = [lo, hi]``, or ``p`` alone: ``0 <= x <= p``);
- ``order_of_magnitude``: ``p / factor <= x <= p factor`` (``factor`` default 10);
- ``below`` / ``above``: ``x < limit`` / ``x > limit`` (``limit`` default ``p``);
- ``at_most``: ``x <= limit``;
- ``holds``: ``x`` is a boolean worked out by the caller (a statement in words).

``not_reproducible`` always gives ``not reproducible here`` (the thesis's means are not
available).

A passing precise check is ``reproduced``, a passing loose one ``consistent``; a claim with
``calibrated: <reason>`` (a target of the project's own fit) is ``calibrated`` when it passes.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from .rows import Row
from .statuses import CALIBRATED, CONSISTENT, DIFFERS, NOT_REPRODUCIBLE, PRECISE_LIMIT, REPRODUCED

__all__ = [
    "DATA_FILES", "Context", "Kind", "KINDS", "CHECK_KINDS", "Claim", "claims", "claim",
    "published_value", "check",
]

#: Data files this module reads by a computed name (pedalrepro.dependencies picks them up as rule
#: inputs): the claims and the published values they reference.
DATA_FILES: tuple[str, ...] = ("data/published/claims.yaml", "data/published/thesis_values.yaml",
                               "data/published/meijaard2007.yaml")


@dataclass(frozen=True)
class Context:
    """What a check kind sees: the published value, the check's parameters, the grid step."""

    rid: str
    pub: Any
    chk: Mapping[str, Any]
    step: float | None = None
    unit: str = ""
    #: The published column's text (what ``equals`` compares a text claim with).
    text: str = ""

    def num(self, x: Any, what: str) -> float:
        """``x`` as a finite float, or a ValueError naming the report item."""
        try:
            out = float(x)
        except (TypeError, ValueError):
            raise ValueError(f"report item {self.rid!r}: {what} {x!r} is not a number") from None
        if not np.isfinite(out):
            raise ValueError(f"report item {self.rid!r}: {what} is not finite ({x})")
        return out

    def limit(self) -> float:
        return self.num(self.chk["limit"] if "limit" in self.chk else self.pub, "limit")

    def bounds(self) -> tuple[Any, Any]:
        return tuple(self.pub) if isinstance(self.pub, list) else (0.0, self.pub)


def _relative_width(bound: float, ctx: Context) -> float:
    p = abs(ctx.num(ctx.pub, "published value"))
    return bound / p if p > 0 else float("inf")


@dataclass(frozen=True)
class Kind:
    """One check kind: its parameters, texts, test and strength.

    ``passes(x, ctx)`` decides the check; ``precise(ctx)`` whether a pass is a reproduction
    (True) or only consistent (False); ``tolerance(ctx)`` and ``published(ctx, fmt)`` are the
    report's texts.
    """

    name: str
    needs: tuple[str, ...]
    passes: Callable[[Any, Context], bool]
    precise: Callable[[Context], bool]
    tolerance: Callable[[Context], str]
    published: Callable[[Context, str], str] = field(
        default=lambda ctx, fmt: fmt.format(ctx.pub))


def _abs_bound(ctx: Context) -> float:
    kind = ctx.chk["kind"]
    if kind == "abs":
        return float(ctx.chk["tol"])
    if kind == "rounds_to":
        return 0.5 * 10.0 ** -int(ctx.chk["decimals"])
    if ctx.step is None:  # half_step
        raise ValueError(f"report item {ctx.rid!r}: half_step needs step=")
    return ctx.step / 2 + 1e-9


def _within(x: Any, ctx: Context) -> bool:
    return abs(ctx.num(x, "reproduced value") - ctx.num(ctx.pub, "published value")) <= \
        _abs_bound(ctx)


def _relative_pass(x: Any, ctx: Context) -> bool:
    p = ctx.num(ctx.pub, "published value")
    return abs(ctx.num(x, "reproduced value") - p) <= float(ctx.chk["tol"]) * abs(p)


def _range_pass(x: Any, ctx: Context) -> bool:
    lo, hi = ctx.bounds()
    x = ctx.num(x, "reproduced value")
    return ctx.num(lo, "lower bound") <= x <= ctx.num(hi, "upper bound")


def _range_text(ctx: Context, fmt: str) -> str:
    lo, hi = ctx.bounds()
    return f"{lo:g}-{hi:g}{ctx.unit}" if isinstance(ctx.pub, list) else f"up to {hi:g}{ctx.unit}"


def _factor(ctx: Context) -> float:
    return float(ctx.chk.get("factor", 10))


def _magnitude_pass(x: Any, ctx: Context) -> bool:
    p, f = ctx.num(ctx.pub, "published value"), _factor(ctx)
    return p / f <= ctx.num(x, "reproduced value") <= p * f


def _bound(op: Callable[[float, float], bool]) -> Callable[[Any, Context], bool]:
    return lambda x, ctx: op(ctx.num(x, "reproduced value"), ctx.limit())


def _equals_pass(x: Any, ctx: Context) -> bool:
    return x == (ctx.pub if ctx.pub is not None else ctx.text)


def _holds_pass(x: Any, ctx: Context) -> bool:
    if not isinstance(x, bool | np.bool_):
        raise ValueError(f"report item {ctx.rid!r}: 'holds' needs a bool, got {x!r}")
    return bool(x)


def _never(ctx: Context) -> bool:
    return False


_BOUND_SIGN = {"below": "< ", "above": "> ", "at_most": "<= "}


def _bound_kind(name: str, op: Callable[[float, float], bool]) -> Kind:
    return Kind(name, (), _bound(op), _never, lambda ctx: name.replace("_", " "),
                lambda ctx, fmt: f"{_BOUND_SIGN[name]}{ctx.limit():g}{ctx.unit}")


#: Every check kind by name (the table of the module docstring).
KINDS: dict[str, Kind] = {k.name: k for k in (
    Kind("abs", ("tol",), _within,
         lambda ctx: _relative_width(_abs_bound(ctx), ctx) <= PRECISE_LIMIT,
         lambda ctx: f"abs {_abs_bound(ctx):g}"),
    Kind("relative", ("tol",), _relative_pass,
         lambda ctx: float(ctx.chk["tol"]) <= PRECISE_LIMIT,
         lambda ctx: f"rel {float(ctx.chk['tol']):g}"),
    Kind("rounds_to", ("decimals",), _within, lambda ctx: True,
         lambda ctx: f"abs {_abs_bound(ctx):g}"),
    Kind("half_step", (), _within,
         lambda ctx: _relative_width(_abs_bound(ctx), ctx) <= PRECISE_LIMIT,
         lambda ctx: f"abs {_abs_bound(ctx):g}"),
    Kind("max_difference", ("limit",), _bound(lambda x, lim: x <= lim),
         lambda ctx: ctx.limit() <= PRECISE_LIMIT,
         lambda ctx: f"max difference {ctx.limit():g}"),
    Kind("range", (), _range_pass, _never, lambda ctx: "inside the published range", _range_text),
    Kind("order_of_magnitude", (), _magnitude_pass, _never,
         lambda ctx: f"same order of magnitude (x/{_factor(ctx):g} .. x{_factor(ctx):g})",
         lambda ctx, fmt: f"~{ctx.pub:g}{ctx.unit}"),
    _bound_kind("below", lambda x, lim: x < lim),
    _bound_kind("above", lambda x, lim: x > lim),
    _bound_kind("at_most", lambda x, lim: x <= lim),
    Kind("equals", (), _equals_pass,
         lambda ctx: isinstance(ctx.pub, int | float) and not isinstance(ctx.pub, bool),
         lambda ctx: "exact"),
    Kind("holds", ("describe",), _holds_pass, _never, lambda ctx: ""),
    Kind("not_reproducible", (), lambda x, ctx: False, _never, lambda ctx: ""),
)}
#: Check kinds and the parameter each needs.
CHECK_KINDS: dict[str, tuple[str, ...]] = {k.name: k.needs for k in KINDS.values()}
_CLAIM_KEYS = {"id", "section", "item", "value", "published_text", "check", "fmt", "unit",
               "wording", "calibrated", "chosen_input", "figures"}


@dataclass(frozen=True)
class Claim:
    """A published claim and how the report checks it (one entry of ``claims.yaml``).

    ``id``, ``item``, ``section``, ``value`` and ``published_text`` are templates: ``{field}``
    is filled from the keyword fields given to :func:`check` (e.g. ``model``, ``coord``), so one
    entry covers e.g. the eight rows "RD 2b <model> <coord>". ``value`` references the published
    number as ``"<file in data/published>:<key>/<key>/..."`` (a list is indexed by position or, for
    a list of mappings, by their ``id``). ``wording`` quotes the thesis text the check's kind and
    tolerance come from; ``calibrated`` gives the reason when the claim is a target of the
    project's own fit; ``chosen_input`` names an input chosen with this claim in view (the report's
    sensitivity rows move it). ``figures`` names the thesis figures and tables the claim is read
    from or checks, each a figure-registry id template (``"fig_3_9"``, ``"table_4_1"``) or a
    registry selector ``{function: <drawing function>, <keyword>: <template>, ...}`` (the figures
    drawn by that function with those keyword arguments, e.g. the RD map of ``{model}``,
    ``{coord}``): each figure in the book shows the status of its rows
    (:mod:`~pedalrepro.report.figure_rows`).
    """

    id: str
    section: str
    item: str
    check: Mapping[str, Any]
    value: str | None = None
    published_text: str | None = None
    fmt: str = "{:.6g}"
    unit: str = ""
    wording: str = ""
    calibrated: str | None = None
    chosen_input: str | None = None
    figures: tuple[Any, ...] = ()
    source: str = field(default="", compare=False)

    @property
    def kind(self) -> str:
        return str(self.check["kind"])


def _claims_file() -> Path:
    from .. import paths

    return paths.PUBLISHED / "claims.yaml"


def _validated(entry: Any, i: int, path: str, seen: Mapping[str, Claim]) -> Claim:
    where = f"{path}: claims[{i}]"
    if not isinstance(entry, dict) or "id" not in entry:
        raise ValueError(f"{where}: every claim needs an 'id'")
    where = f"{path}: claim {entry['id']!r}"
    unknown = set(entry) - _CLAIM_KEYS
    missing = {"section", "item", "check", "wording"} - set(entry)
    if unknown or missing:
        raise ValueError(f"{where}: unknown keys {sorted(unknown)}, missing {sorted(missing)}")
    chk = entry["check"]
    kind = chk.get("kind") if isinstance(chk, dict) else None
    if kind not in KINDS:
        raise ValueError(f"{where}: check kind {kind!r} not in {sorted(KINDS)}")
    need = [k for k in KINDS[kind].needs if k not in chk]
    if need:
        raise ValueError(f"{where}: check kind {kind!r} needs {need}")
    if entry.get("value") is None and entry.get("published_text") is None:
        raise ValueError(f"{where}: needs a published 'value' reference or 'published_text'")
    if not str(entry.get("wording") or "").strip():
        raise ValueError(f"{where}: 'wording' must quote the thesis text of the claim")
    if entry["id"] in seen:
        raise ValueError(f"{where}: duplicate id")
    figures = entry.get("figures", [])
    if not isinstance(figures, list) or not all(
            isinstance(f, str) and f.strip()
            or isinstance(f, dict) and isinstance(f.get("function"), str) for f in figures):
        raise ValueError(f"{where}: 'figures' must be a list of figure ids or of mappings with "
                         f"a 'function' (a registry selector), got {figures!r}")
    entry = {**entry, "figures": tuple(figures)}
    return Claim(**entry, source=path)


@lru_cache(maxsize=4)
def _load_claims(path: str) -> dict[str, Claim]:
    from ..yamlio import read_mapping

    data = read_mapping(path)
    out: dict[str, Claim] = {}
    for i, entry in enumerate(data.get("claims") or []):
        c = _validated(entry, i, path, out)
        out[c.id] = c
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
    from .. import paths
    from ..yamlio import read_mapping

    file, _, keys = reference.format(**fields).partition(":")
    node: Any = read_mapping(paths.PUBLISHED / file)
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


def _published_text(c: Claim, ctx: Context, fields: Mapping[str, Any]) -> tuple[str, dict]:
    text_fields = dict(fields, value=ctx.pub)
    if c.kind == "range" and ctx.pub is not None:
        lo, hi = ctx.bounds()
        text_fields.update(lo=lo, hi=hi)
    if c.published_text is not None:
        return _fill(c.published_text, text_fields, "published_text", c.id), text_fields
    return KINDS[c.kind].published(ctx, c.fmt), text_fields


def check(
    claim_or_id: Claim | str,
    value: Any,
    *,
    shown: str | None = None,
    label: str = "",
    note: str = "",
    step: float | None = None,
    unavailable: str | None = None,
    calibrated: str | None = None,
    **fields: Any,
) -> Row:
    """The report row of a published claim and the pipeline's value: the one place a status is
    decided (check kinds: module docstring; statuses: :mod:`pedalrepro.report.statuses`).

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
    calibrated
        If given and the check passes, the status is ``calibrated`` and the reason is added to
        the note (an input chosen with this number in view, found not robust by the caller's
        sensitivity run); the claim's own ``calibrated`` reason does the same for every row.
    **fields
        Fill the claim's templates (``{model}``, ``{coord}``, ...).
    """
    c = claim_or_id if isinstance(claim_or_id, Claim) else claim(claim_or_id)
    rid = _fill(c.id, fields, "id", c.id)
    pub = published_value(c.value, **fields) if c.value is not None else None
    kind = KINDS[c.kind]
    ctx = Context(rid, pub, dict(c.check), step, f" {c.unit}" if c.unit else "")
    published, text_fields = _published_text(c, ctx, fields)
    ctx = replace(ctx, text=published)
    skipped = unavailable is not None or c.kind == "not_reproducible"
    if c.kind == "half_step" and step is None and skipped:
        tol = "abs 0"
    else:
        tol = kind.tolerance(ctx)
    tol = ctx.chk.get("describe", tol)
    if skipped:
        status = NOT_REPRODUCIBLE
        note = note or (unavailable or "")
        if value is None and shown is None:
            shown = "n/a"
    else:
        ok = kind.passes(value, ctx)
        reason = calibrated or c.calibrated
        if not ok:
            status = DIFFERS
        elif reason:
            status = CALIBRATED
            note = f"{note} Calibrated: {reason}".strip() if note else f"Calibrated: {reason}"
        else:
            status = REPRODUCED if kind.precise(ctx) else CONSISTENT
    if shown is None:
        numeric = isinstance(value, int | float | np.number) and not isinstance(value, bool)
        shown = c.fmt.format(value) if numeric else str(value)
    return Row(_fill(c.item, text_fields, "item", c.id), _fill(c.section, fields, "section", c.id),
               published, shown + label, tol, status, note, id=rid)
