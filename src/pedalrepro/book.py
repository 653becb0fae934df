"""The book's HTML helpers, in one place: figures and tables under their thesis id, reader tables,
paragraphs that are either filled or replaced by one note, and the check of the built pages.

The notebooks call these (``from pedalrepro import book``); :mod:`pedalrepro.figures` re-exports
:func:`show`, :func:`figure_html`, :func:`thesis_label` and the ``BOOK_*_HREF`` constants for the
notebooks that call them there. Importing this module changes nothing in IPython: a notebook that
glues numpy scalars asks for plain numbers with :func:`setup`.

Figures in the book (CONTRIBUTING.md, "Figures in the book"): every image is a ``<figure
class="pedalrepro-figure">`` with a caption and a link to its full-size file. A figure the
pipeline wrote (``results/figures/...``) is linked as a file (``<img src="../figures/...">``),
never inlined, so no page carries megabytes of base64; the book rule copies
``results/figures`` beside the pages.
"""

from __future__ import annotations

import html as _html
import re
import string
from collections.abc import Callable, Mapping
from pathlib import Path

from . import paths

__all__ = [
    "BOOK_FIGURES_HREF", "BOOK_TABLES_HREF", "PLACEHOLDERS", "thesis_label", "BEYOND_THESIS",
    "figure_anchor", "pages_showing", "figure_html", "file_figure_html", "UNITS", "header",
    "runs_as_columns", "table_html", "reader_table", "show_table", "show", "show_file", "Text",
    "fill", "note_html", "paragraph", "plain_numbers_in_notebooks", "setup", "reader_text",
    "placeholder_problems", "EXECUTED_PATTERNS", "stderr_problems", "execute_notebook",
    "stage_source",
]

#: Where the book serves the figure files, relative to a chapter page (``notebooks/*.html``):
#: the rule ``book`` copies ``results/figures`` to ``_build/html/figures``.
BOOK_FIGURES_HREF = "../figures/"
#: ... and the result tables, from ``results/tables`` (the same copy, subfolders included).
BOOK_TABLES_HREF = "../tables/"
#: Text that must never reach a reader: the stand-ins that earlier builds glued into sentences
#: when an input was missing, and numpy reprs of glued scalars.
PLACEHOLDERS: tuple[str, ...] = (
    "(no real run in this build)", "(not computed in this build)", "(not built)",
    "np.float64(", "np.int64(", "np.float32(", "np.bool_(")


def thesis_label(figure_id: str) -> str:
    """Thesis number of a figure/table id: ``"fig_2_3"`` -> ``"Figure 2.3"``, ``"table_d_1"`` ->
    ``"Table D.1"``; a registered figure that is not the thesis's (``periodic_maps_HR``,
    :data:`pedalrepro.figures.registry.FIGURES`) -> ``"Beyond the thesis"``."""
    kind, _, number = figure_id.partition("_")
    if kind not in ("fig", "table") or not number:
        from .figures.registry import FIGURES

        if figure_id in FIGURES:
            return BEYOND_THESIS
        raise ValueError(f"figure id {figure_id!r} is not fig_<chapter>_<n> or table_<chapter>_<n>")
    parts = [p.upper() if p.isalpha() else p for p in number.split("_")]
    return ("Table " if kind == "table" else "Figure ") + ".".join(parts)


#: The label of a registered figure that the thesis does not have (:func:`thesis_label`).
BEYOND_THESIS = "Beyond the thesis"


def figure_anchor(figure_id: str) -> str:
    """The HTML id of a figure or table in the book (``"pedalrepro-fig_g_2"``): other pages link
    ``<page>.html#<anchor>``."""
    thesis_label(figure_id)  # a bad id fails here
    return f"pedalrepro-{figure_id}"


def pages_showing(figure_ids, notebooks_dir: Path | None = None) -> dict[str, str]:
    """Which book notebook shows each figure id (the notebook whose code names it in quotes), as
    ``{id: "notebooks/<stem>"}``; ids no notebook names are left out."""
    import json

    folder = Path(notebooks_dir) if notebooks_dir is not None else paths.ROOT / "notebooks"
    sources = {}
    for nb in sorted(folder.glob("*.ipynb")):
        cells = json.loads(nb.read_text())["cells"]
        sources[nb.stem] = "\n".join("".join(c["source"]) for c in cells
                                     if c["cell_type"] == "code")
    found = {}
    for fid in figure_ids:
        for stem, code in sources.items():
            if f'"{fid}"' in code or f"'{fid}'" in code:
                found[fid] = f"notebooks/{stem}"
                break
    return found


def _figure_src(path: Path) -> str | None:
    """The book's address of a file under the results' figure folder, or None if it is not one."""
    try:
        rel = Path(path).resolve().relative_to(paths.figures().resolve())
    except ValueError:
        return None
    return BOOK_FIGURES_HREF + rel.as_posix()


def _img(src: str, alt: str, href: str | None) -> str:
    body = f'<img src="{src}" alt="{_html.escape(alt)}" style="max-width:100%;height:auto">'
    if href:
        body = (f'<a class="pedalrepro-full-size" href="{href}" title="open full size">'
                f"{body}</a>")
    return body


def _downloads(png_href: str, pdf_href: str | None) -> str:
    links = f'<a href="{png_href}">PNG</a>'
    if pdf_href:
        links += f' · <a href="{pdf_href}">PDF (vector)</a>'
    return f' <span class="pedalrepro-downloads">Full size: {links}</span>'


def figure_html(figure_id: str, png: bytes | None = None, *, src: str | None = None,
                table_html: str | None = None, caption: str = "", link: bool = False) -> str:
    """The HTML element the book shows for one figure or table id (see CONTRIBUTING.md,
    "Figures in the book"): ``<figure class="pedalrepro-figure" id="pedalrepro-<id>"
    data-figure-id="<id>">`` holding an ``<img alt="<id> ...">`` or an HTML table, and a caption
    led by the thesis number.

    ``src``: the image's address (a file served beside the book, :data:`BOOK_FIGURES_HREF`);
    ``png``: the image's bytes, embedded as a data URI (only for a figure drawn in the notebook,
    which has no file). ``link``: the image opens the full-size PNG, and the caption links the PNG
    and the PDF (vector) served beside the book; for a table, the caption links its CSV
    (:data:`BOOK_TABLES_HREF`)."""
    import base64

    label = thesis_label(figure_id)
    lead = label if label == BEYOND_THESIS else f"{label} of the thesis"
    cap = f"<strong>{lead}</strong> (<code>{figure_id}</code>)"
    if caption:
        cap += ". " + _html.escape(caption)
    if png is not None or src is not None:
        href = f"{BOOK_FIGURES_HREF}{figure_id}"
        if src is None:
            src = "data:image/png;base64," + base64.b64encode(png).decode("ascii")
        body = _img(src, f"{figure_id}: {label}", f"{href}.png" if link else None)
        if link:
            cap += _downloads(f"{href}.png", f"{href}.pdf")
    elif table_html is not None:
        body = f'<div class="pedalrepro-table" style="overflow-x:auto">{table_html}</div>'
        if link:
            cap += (f' <span class="pedalrepro-downloads">Download: <a '
                    f'href="{BOOK_TABLES_HREF}{figure_id}.csv">CSV</a></span>')
    else:
        raise ValueError("figure_html needs png=, src= or table_html=")
    if _FIGURE_STATUS is not None:
        cap += _FIGURE_STATUS(figure_id)
    return (f'<figure class="pedalrepro-figure" id="{figure_anchor(figure_id)}" '
            f'data-figure-id="{figure_id}">{body}<figcaption>{cap}</figcaption></figure>')


def file_figure_html(path: str | Path, caption: str) -> str:
    """A figure the pipeline wrote that is not a thesis figure (``results/figures/<sub>/<x>.png``:
    the own-bicycle map, the real run's panel, ...): ``<figure class="pedalrepro-figure"
    data-figure-file="<sub>/<x>">``, linked as a file, the caption in our words and the links to
    the full-size PNG and, when it exists, the PDF."""
    path = Path(path)
    if not caption.strip():
        raise ValueError(f"{path.name}: a figure in the book needs a caption")
    src = _figure_src(path)
    if src is None:
        raise ValueError(f"{path}: not under the results' figure folder {paths.figures()}")
    if not path.exists():
        raise FileNotFoundError(f"{path} does not exist (run the pipeline)")
    pdf = path.with_suffix(".pdf")
    pdf_href = src[:-len(path.suffix)] + ".pdf" if pdf.exists() else None
    name = src.removeprefix(BOOK_FIGURES_HREF).rsplit(".", 1)[0]
    cap = _html.escape(caption) + _downloads(src, pdf_href)
    return (f'<figure class="pedalrepro-figure" data-figure-file="{name}">'
            f"{_img(src, name, src)}<figcaption>{cap}</figcaption></figure>")


#: Column-name endings and the unit a reader's header shows for them (longest first).
UNITS: tuple[tuple[str, str], ...] = (
    ("_n_m_rad", "N m/rad"), ("_rad_rad", "rad/rad"), ("_rad_m", "rad/m"), ("_1_s", "1/s"),
    ("_rad_s", "rad/s"), ("_m_s", "m/s"), ("_kmh", "km/h"), ("_rpm", "rpm"), ("_percent", "%"),
    ("_pct", "%"), ("_rad", "rad"), ("_deg", "deg"), ("_nm", "N m"), ("_n", "N"), ("_hz", "Hz"),
    ("_kg", "kg"), ("_ms", "ms"), ("_m", "m"), ("_s", "s"))


def header(column: str) -> str:
    """A reader's column header from a CSV column name: underscores as spaces, the unit ending in
    parentheses (``"roll_model_rad"`` -> ``"roll model (rad)"``, ``"speed_kmh"`` ->
    ``"speed (km/h)"``); a name without a unit ending is only de-underscored."""
    name = str(column)
    for end, unit in UNITS:
        if name.lower().endswith(end) and len(name) > len(end):
            return f"{name[:-len(end)].replace('_', ' ')} ({unit})"
    return name.replace("_", " ")


def runs_as_columns(df, label: list[str] | tuple[str, ...], *, first: str = "quantity"):
    """A table with one row per run turned as the thesis prints Table 4.1: one column per run
    (headed by the ``label`` columns joined, e.g. "HR 18.1 km/h"), one row per quantity (headed
    with :func:`header`)."""
    import pandas as pd

    def part(col, value):
        if pd.isna(value):
            return ""
        if col.endswith("_kmh"):
            return f"{value:g} km/h"
        return str(value)

    names = [" ".join(p for c in label if (p := part(c, r[c]))) for _, r in df.iterrows()]
    body = df.drop(columns=list(label))
    out = pd.DataFrame(body.to_numpy().T, columns=names, index=[header(c) for c in body.columns])
    out.index.name = first
    return out.reset_index()


def _cell(x, float_format: str) -> str:
    import numbers

    import pandas as pd

    if isinstance(x, str):
        return x if x.strip() else "-"
    if x is None or (not isinstance(x, (list, tuple)) and pd.isna(x)):
        return "-"
    if isinstance(x, (bool,)) or (hasattr(x, "dtype") and x.dtype.kind == "b"):
        return str(bool(x))
    if isinstance(x, numbers.Integral):
        return str(int(x))
    if isinstance(x, numbers.Real):
        return float_format.format(float(x))
    return str(x)


def table_html(df, *, float_format: str = "{:.6g}", index: bool = False,
               units: bool = True) -> str:
    """The bare ``<table>`` of :func:`reader_table` (no scroll container)."""
    if index:
        df = df.reset_index()
    if units:
        df = df.rename(columns=header)
    cells = df.map(lambda x: _cell(x, float_format))
    return cells.to_html(index=False, border=0, classes="table", max_rows=None, max_cols=None,
                         escape=True)


def reader_table(df, *, float_format: str = "{:.6g}", index: bool = False,
                 units: bool = True) -> str:
    """A table as a reader sees it: no index column (unless ``index``), "-" for a missing value,
    every row and column (no "..."), numbers with ``float_format``, headers with their units
    (:func:`header`, unless ``units=False``), in a scroll container so a wide table never runs
    past the column."""
    table = table_html(df, float_format=float_format, index=index, units=units)
    return f'<div class="pedalrepro-table" style="overflow-x:auto">{table}</div>'


def show_table(df, caption: str = "", **kwargs) -> None:
    """Display :func:`reader_table` of ``df`` (with an optional caption below it)."""
    from IPython.display import HTML, display

    cap = f'<p class="pedalrepro-table-caption"><em>{_html.escape(caption)}</em></p>' \
        if caption else ""
    display(HTML(reader_table(df, **kwargs) + cap))


def show(obj=None, figure_id: str = "", caption: str = "", *, float_format: str = "{:.6g}"):
    """Display a figure or table in a notebook so the book shows it under its thesis id.

    Parameters
    ----------
    obj : matplotlib.figure.Figure, pandas.DataFrame, str, pathlib.Path or None
        The figure (it is closed afterwards, so the inline backend does not show it twice), a
        table, a PNG/CSV file, or None to show the pipeline's own ``results/figures/<id>.png`` or
        ``results/tables/<id>.csv``. A figure is linked to the rule's full-size PNG and PDF when
        they exist; a rule's PNG is linked as a file, not embedded.
    figure_id : str
        The id of ``data/figure_ids.yaml`` (``"fig_2_3"``, ``"table_d_1"``).
    caption : str
        The caption in our own words; the thesis number is prepended.

    Examples
    --------
    >>> from pedalrepro import book, figures
    >>> book.show(figures.draw("fig_2_3"), "fig_2_3", "Right-leg COM.")  # doctest: +SKIP
    >>> book.show(None, "fig_3_10", "Model HS, roll.")   # the rule's file  # doctest: +SKIP
    """
    import io

    import matplotlib.pyplot as plt
    import pandas as pd
    from IPython.display import display

    from .figures.page import check_legible, style

    if not figure_id:
        raise ValueError("figures.show needs the figure id (e.g. 'fig_2_3')")
    thesis_label(figure_id)  # a bad id fails here, before any file is read
    if obj is None:
        fig_path, table_path = paths.figure(figure_id), paths.table(figure_id)
        obj = table_path if figure_id.startswith("table_") else fig_path
        if not Path(obj).exists():
            raise FileNotFoundError(f"{figure_id}: {obj} does not exist (run the pipeline)")
    bundle = {"text/plain": f"{thesis_label(figure_id)} ({figure_id})"}
    if isinstance(obj, (str, Path)) and str(obj).endswith(".csv"):
        obj = pd.read_csv(obj)
    link = paths.figure(figure_id).exists() and paths.figure(figure_id, fmt="pdf").exists()
    if isinstance(obj, pd.DataFrame):
        table = table_html(obj, float_format=float_format)
        bundle["text/html"] = figure_html(figure_id, table_html=table, caption=caption,
                                          link=paths.table(figure_id).exists())
    elif isinstance(obj, (str, Path)) and _figure_src(Path(obj)) is not None:
        bundle["text/html"] = figure_html(figure_id, src=_figure_src(Path(obj)), caption=caption,
                                          link=link)
    else:
        if isinstance(obj, (str, Path)):
            png = Path(obj).read_bytes()
        else:
            check_legible(obj, figure_id)
            buf = io.BytesIO()
            with style():
                obj.savefig(buf, format="png")
            plt.close(obj)
            png = buf.getvalue()
        import base64

        bundle["text/html"] = figure_html(figure_id, png, caption=caption, link=link)
        bundle["image/png"] = base64.b64encode(png).decode("ascii")
    display(bundle, raw=True)


def show_file(path: str | Path, caption: str) -> None:
    """Display :func:`file_figure_html` (a pipeline figure that is not a thesis figure)."""
    from IPython.display import display

    path = Path(path)
    display({"text/plain": path.name, "text/html": file_figure_html(path, caption)}, raw=True)


class Text(str):
    """A glued string shown without quotes (``glue(name, Text("3045"))``)."""

    def __repr__(self) -> str:
        return str(self)


def fill(template: str, values: Mapping[str, object]) -> str:
    """``template`` with every ``{name}`` / ``{name:fmt}`` replaced from ``values``; a field with
    no value, or a value that is None or an empty string, raises KeyError naming it (a template
    is always filled, never shown with its braces)."""
    fields = {f for _, f, _, _ in string.Formatter().parse(template) if f is not None}
    missing = sorted(f for f in fields if f not in values or values[f] is None
                     or (isinstance(values[f], str) and not values[f].strip()))
    if missing:
        raise KeyError(f"template fields without a value: {missing}")
    return template.format_map(values)


def note_html(missing: str, how: str, title: str = "Not in this build") -> str:
    """One note in place of a paragraph whose input is missing: what is missing, and how to get
    it."""
    return (f'<div class="admonition note pedalrepro-missing"><p class="admonition-title">'
            f"{_html.escape(title)}</p><p>{missing} {how}</p></div>")


def paragraph(template: str, values: Mapping[str, object] | None, *, missing: str,
              how: str) -> str:
    """A paragraph (Markdown) filled from ``values`` with :func:`fill`, or, when ``values`` is
    None (its input is missing in this build), the note of :func:`note_html`. Displayed in a
    notebook with ``display(Markdown(...))``; returned for tests."""
    from IPython.display import HTML, Markdown, display

    if values is None:
        out = note_html(missing, how)
        display(HTML(out))
    else:
        out = fill(template, values)
        display(Markdown(out))
    return out


def plain_numbers_in_notebooks() -> bool:
    """Show numpy scalars as plain numbers (``3.15``, not ``np.float64(3.15)``) in IPython.

    numpy 2 changed the repr of its scalars; myst-nb's ``glue`` stores that repr as text/plain, and
    ``{glue:text}`x:.2f``` then cannot parse it (a warning, so the strict book build fails). Called
    by :func:`setup` in a notebook that asks; a no-op outside IPython. Returns whether a kernel
    was found.
    """
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython comes with the notebook stack
        return False
    shell = get_ipython()
    if shell is None:
        return False
    import numpy as np

    plain = shell.display_formatter.formatters["text/plain"]
    # concrete classes: IPython stops at the first class in the MRO that defines __repr__
    for cls in (np.float16, np.float32, np.float64, np.longdouble):
        plain.for_type(cls, lambda x, p, cycle: p.text(repr(float(x))))
    for cls in (np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64):
        plain.for_type(cls, lambda x, p, cycle: p.text(repr(int(x))))
    plain.for_type(np.bool_, lambda x, p, cycle: p.text(repr(bool(x))))
    return True


#: Set by :func:`setup`: figure id -> the report-status HTML its caption ends with.
_FIGURE_STATUS: Callable[[str], str] | None = None


def setup(figure_status: Callable[[str], str] | None = None) -> bool:
    """What a book notebook asks for at its top: numpy scalars glued as plain numbers
    (:func:`plain_numbers_in_notebooks`) and pandas showing every row and column (no "...").

    ``figure_status``: figure id -> HTML (``pedalrepro.report.figure_rows.caption_status()``):
    every thesis figure or table :func:`figure_html` shows from then on ends its caption with the
    status of the report rows checking it. This module does not import the report itself, so
    that the figure rules, which import it, do not depend on the claims.
    Returns whether a kernel was found."""
    import pandas as pd

    global _FIGURE_STATUS
    _FIGURE_STATUS = figure_status

    pd.set_option("display.max_columns", None)
    pd.set_option("display.max_colwidth", None)
    pd.set_option("display.width", None)
    return plain_numbers_in_notebooks()


# --- the built pages ------------------------------------------------------------------------
_SKIP_TAGS = ("script", "style", "pre", "code", "head", "mjx-container", "textarea")
_BRACES = re.compile(r"\{[A-Za-z_][A-Za-z0-9_]*(?:[:!][^{}]*)?\}")


def reader_text(page_html: str) -> str:
    """The text a reader sees on a built page: tags stripped, without scripts, styles, code, math
    (``\\(...\\)``, ``$$...$$``) and the navigation."""
    from html.parser import HTMLParser

    # a plain parser with a stack, so that nested spans inside a skipped block are handled
    class _Stack(HTMLParser):
        def __init__(self):
            super().__init__()
            self.stack: list[bool] = []
            self.parts: list[str] = []

        def handle_starttag(self, tag, attrs):
            if tag in ("br", "img", "hr", "input", "meta", "link", "wbr", "source"):
                return
            cls = (dict(attrs).get("class") or "").split()
            skip = tag in _SKIP_TAGS or tag == "nav" or "math" in cls
            self.stack.append(skip or (bool(self.stack) and self.stack[-1]))

        def handle_endtag(self, tag):
            if tag in ("br", "img", "hr", "input", "meta", "link", "wbr", "source"):
                return
            if self.stack:
                self.stack.pop()

        def handle_data(self, data):
            if not (self.stack and self.stack[-1]):
                self.parts.append(data)

    parser = _Stack()
    parser.feed(page_html)
    text = " ".join(parser.parts)
    text = re.sub(r"\\\(.*?\\\)|\$\$.*?\$\$|\\\[.*?\\\]", " ", text, flags=re.S)
    return re.sub(r"\s+", " ", text)


def placeholder_problems(page_html: str, name: str = "page") -> list[str]:
    """What a reader must never see on a built page: a known placeholder
    (:data:`PLACEHOLDERS`), an unfilled ``{field}`` template in the text, and an empty glued
    value (myst-nb's ``<span class="pasted-text"></span>``)."""
    problems = []
    text = reader_text(page_html)
    for p in PLACEHOLDERS:
        if p in text:
            problems.append(f"{name}: placeholder {p!r} x{text.count(p)}")
    for m in _BRACES.finditer(text):
        ctx = text[max(0, m.start() - 40):m.end() + 20]
        problems.append(f"{name}: unfilled template {m.group(0)!r} in '...{ctx}...'")
    for m in re.finditer(r'<span class="pasted-text">\s*(?:nan|NaN)?\s*</span>', page_html):
        ctx = reader_text(page_html[max(0, m.start() - 300):m.start()])[-60:]
        problems.append(f"{name}: empty or NaN glued value after '...{ctx}'")
    return problems


# --------------------------------------------------------------------------------------------
# Building the book (rules/book.smk): each notebook executed in its own job, then one Sphinx
# build of a staging copy of book/ that executes only the MyST text notebooks.
# --------------------------------------------------------------------------------------------

#: What ``execute.exclude_patterns`` of the staged ``_config.yml`` holds (:func:`stage_source`):
#: the notebooks, executed beforehand by :func:`execute_notebook`, are not executed again.
EXECUTED_PATTERNS: tuple[str, ...] = ("notebooks/*",)


def stderr_problems(nb, stderr_output: str = "error") -> list[str]:
    """The cells of an executed notebook whose stderr output fails the strict build.

    myst-nb checks stderr when it renders a page (``nb_output_stderr``, jupyter-book's
    ``execute.stderr_output``): with ``"error"`` or ``"severe"`` each code cell with a stderr
    stream output logs an error, which ``-W`` turns into a failed build. This is that check, run
    as soon as the notebook is executed; the final build still makes it (the outputs are kept).

    Parameters
    ----------
    nb : nbformat.NotebookNode
        The executed notebook.
    stderr_output : str
        The book's setting (``execute.stderr_output`` of ``book/_config.yml``); a notebook's or
        a cell's ``mystnb: {output_stderr: ...}`` metadata overrides it, a cell tagged
        ``remove-stderr`` is never reported, as in myst-nb.

    Returns
    -------
    list of str
        One message per failing cell, ``"stderr was found in the cell outputs of cell <n>:
        <text>"`` (cells counted from 1, as myst-nb does); empty when none fails.
    """
    document = nb.metadata.get("mystnb", {}).get("output_stderr", stderr_output)
    problems = []
    for index, cell in enumerate(nb.cells):
        if cell.cell_type != "code" or "remove-stderr" in cell.metadata.get("tags", []):
            continue
        level = cell.metadata.get("mystnb", {}).get("output_stderr", document)
        if level not in ("error", "severe"):
            continue
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out.get("name") == "stderr":
                problems.append(f"stderr was found in the cell outputs of cell {index + 1}: "
                                f"{out.get('text', '').strip()[:500]}")
                break
    return problems


def execute_notebook(source: str | Path, output: str | Path, *, cwd: str | Path | None = None,
                     timeout: int | None = 120, stderr_output: str = "error",
                     kernel_name: str = "python3") -> float:
    """Execute one book notebook as jupyter-book does (myst-nb's ``force`` mode) and write it.

    The kernel runs in ``cwd`` (default: the notebook's folder, ``notebooks/``, where
    jupyter-book ran it), every cell with ``timeout``, no error allowed; a notebook's
    ``execution`` metadata (``timeout``, ``allow_errors``) overrides both, as in myst-nb. The
    executed notebook keeps its outputs, so the book renders them without executing it again
    (:data:`EXECUTED_PATTERNS`).

    Parameters
    ----------
    source : str or pathlib.Path
        The notebook (``notebooks/<stem>.ipynb``).
    output : str or pathlib.Path
        Where the executed notebook is written (its folder is created); nothing is written when
        the execution fails.
    cwd : str or pathlib.Path, optional
        The kernel's working directory.
    timeout : int or None
        Seconds a cell may run (``execute.timeout`` of ``book/_config.yml``).
    stderr_output : str
        ``execute.stderr_output`` of the book: ``"error"`` or ``"severe"`` fail on a cell
        writing to stderr (:func:`stderr_problems`).
    kernel_name : str
        The Jupyter kernel.

    Returns
    -------
    float
        The execution's wall time in seconds.

    Raises
    ------
    RuntimeError
        A cell failed or timed out (the message names the notebook and holds the cell's source
        and traceback), or a cell wrote to stderr.
    """
    import time

    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError, CellTimeoutError

    source, output = Path(source), Path(output)
    nb = nbformat.read(source, as_version=4)
    meta = nb.metadata.get("execution", {})
    timeout = meta.get("timeout", timeout)
    allow_errors = meta.get("allow_errors", False)
    folder = Path(cwd) if cwd is not None else source.resolve().parent
    client = NotebookClient(nb, timeout=timeout, allow_errors=allow_errors,
                            kernel_name=kernel_name, record_timing=False,
                            resources={"metadata": {"path": str(folder)}})
    start = time.perf_counter()
    try:
        client.execute()
    except (CellExecutionError, CellTimeoutError) as err:
        raise RuntimeError(f"{source}: executing the notebook failed\n{err}") from err
    seconds = time.perf_counter() - start
    problems = stderr_problems(nb, stderr_output)
    if problems:
        raise RuntimeError(f"{source}: " + "\n".join(problems)
                           + f"\n(execute.stderr_output is {stderr_output!r})")
    output.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, output)
    return seconds


def stage_source(book_dir: str | Path, executed: list[str | Path], dest: str | Path) -> Path:
    """The source folder the final book build reads: ``book/`` with the executed notebooks.

    ``dest`` is emptied and filled with copies of ``book_dir``'s files (the pages, ``_toc.yml``)
    and folders, a link to each ``html_static_path`` folder (``_mathjax``), the ``executed``
    notebooks in ``notebooks/`` (instead of the link to the repository's ``notebooks/``), and
    ``_config.yml`` with :data:`EXECUTED_PATTERNS` added to ``execute.exclude_patterns``: the
    build renders the executed notebooks as they are and still executes the MyST text notebooks
    (``book/*.md``). Page names, hence the book's URLs, are those of ``book_dir``.

    Parameters
    ----------
    book_dir : str or pathlib.Path
        The book's source (``book/``).
    executed : list of str or pathlib.Path
        The executed notebooks (:func:`execute_notebook`), named as in ``notebooks/``.
    dest : str or pathlib.Path
        The staging folder (``<results>/book/src``).

    Returns
    -------
    pathlib.Path
        ``dest``.
    """
    import shutil

    import yaml

    book_dir, dest = Path(book_dir).resolve(), Path(dest)
    config = yaml.safe_load((book_dir / "_config.yml").read_text())
    static = set(config.get("sphinx", {}).get("config", {}).get("html_static_path", []))
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    for entry in sorted(book_dir.iterdir()):
        if entry.name in ("notebooks", "_build", "_config.yml"):
            continue
        if entry.name in static:
            (dest / entry.name).symlink_to(entry)
        elif entry.is_dir():
            shutil.copytree(entry, dest / entry.name)
        else:
            shutil.copy2(entry, dest / entry.name)
    (dest / "notebooks").mkdir()
    for nb in executed:
        shutil.copy2(nb, dest / "notebooks" / Path(nb).name)
    execute = config.setdefault("execute", {})
    patterns = list(execute.get("exclude_patterns", []))
    execute["exclude_patterns"] = patterns + [p for p in EXECUTED_PATTERNS if p not in patterns]
    (dest / "_config.yml").write_text(
        f"# {book_dir / '_config.yml'} with the executed notebooks excluded from execution\n"
        "# (pedalrepro.book.stage_source)\n" + yaml.safe_dump(config, sort_keys=False))
    return dest
