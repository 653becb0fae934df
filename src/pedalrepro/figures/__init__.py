"""One function per thesis figure: arrays/DataFrames in, a matplotlib ``Figure`` out.

Every figure is registered in ONE table, :mod:`pedalrepro.figures.registry` (id -> drawing
function and the files it reads), which the Snakemake rules (``rules/figures.smk``: inputs,
outputs, :func:`registry.write`) and the notebooks (:func:`draw`, ``show(None, id)``) both use.
Drawing functions by thesis part: ``section2``, ``linear``, ``nonlinear``, ``validation``; model
colours and method line styles in ``palette``.

Figures are drawn for the page: at most :data:`MAX_WIDTH_IN` (the book's 672 px content width)
wide, with no text below :data:`MIN_FONT_PT`; :func:`save` refuses a figure that is not, and
writes a PNG and a PDF (vector) beside it; the book links each figure to both.
"""

from __future__ import annotations

from pathlib import Path

from .. import paths
from .page import (  # noqa: F401  (the package's public names)
    MAX_WIDTH_IN,
    MIN_FONT_PT,
    check_legible,
    save,
    style,
    synthetic_stamp,
)


def thesis_label(figure_id: str) -> str:
    """Thesis number of a figure/table id: ``"fig_2_3"`` -> ``"Figure 2.3"``, ``"table_d_1"`` ->
    ``"Table D.1"``; a registered figure that is not the thesis's (``periodic_maps_HR``,
    :data:`.registry.FIGURES`) -> ``"Beyond the thesis"``."""
    kind, _, number = figure_id.partition("_")
    if kind not in ("fig", "table") or not number:
        from .registry import FIGURES

        if figure_id in FIGURES:
            return BEYOND_THESIS
        raise ValueError(f"figure id {figure_id!r} is not fig_<chapter>_<n> or table_<chapter>_<n>")
    parts = [p.upper() if p.isalpha() else p for p in number.split("_")]
    return ("Table " if kind == "table" else "Figure ") + ".".join(parts)


#: The label of a registered figure that the thesis does not have (:func:`thesis_label`).
BEYOND_THESIS = "Beyond the thesis"


#: Where the book serves the figure files, relative to a chapter page (``notebooks/*.html``):
#: the rule ``book`` copies ``results/figures`` to ``_build/html/figures``.
BOOK_FIGURES_HREF = "../figures/"
#: ... and the result tables, from ``results/tables`` (the same copy, subfolders included).
BOOK_TABLES_HREF = "../tables/"


def figure_html(figure_id: str, png: bytes | None = None, *, table_html: str | None = None,
                caption: str = "", link: bool = False) -> str:
    """The HTML element the book shows for one figure or table id (see CONTRIBUTING.md,
    "Figures in the book"): ``<figure class="pedalrepro-figure" id="pedalrepro-<id>"
    data-figure-id="<id>">`` holding an ``<img alt="<id> ...">`` (PNG embedded as a data URI, so
    the page needs no other file) or an HTML table, and a caption led by the thesis number.

    ``link``: the image opens the full-size PNG, and the caption links the PNG and the PDF (vector)
    served beside the book (:data:`BOOK_FIGURES_HREF`); for a table, the caption links its CSV
    (:data:`BOOK_TABLES_HREF`)."""
    import base64
    import html

    label = thesis_label(figure_id)
    lead = label if label == BEYOND_THESIS else f"{label} of the thesis"
    cap = f"<strong>{lead}</strong> (<code>{figure_id}</code>)"
    if caption:
        cap += ". " + html.escape(caption)
    if png is not None:
        data = base64.b64encode(png).decode("ascii")
        body = (f'<img src="data:image/png;base64,{data}" alt="{figure_id}: {label}" '
                'style="max-width:100%;height:auto">')
        if link:
            href = f"{BOOK_FIGURES_HREF}{figure_id}"
            body = (f'<a class="pedalrepro-full-size" href="{href}.png" '
                    f'title="open full size">{body}</a>')
            cap += (f' <span class="pedalrepro-downloads">Full size: <a href="{href}.png">PNG'
                    f'</a> · <a href="{href}.pdf">PDF (vector)</a></span>')
    elif table_html is not None:
        body = f'<div class="pedalrepro-table" style="overflow-x:auto">{table_html}</div>'
        if link:
            cap += (f' <span class="pedalrepro-downloads">Download: <a '
                    f'href="{BOOK_TABLES_HREF}{figure_id}.csv">CSV</a></span>')
    else:
        raise ValueError("figure_html needs png= or table_html=")
    return (f'<figure class="pedalrepro-figure" id="pedalrepro-{figure_id}" '
            f'data-figure-id="{figure_id}">{body}<figcaption>{cap}</figcaption></figure>')


def show(obj=None, figure_id: str = "", caption: str = "", *, float_format: str = "{:.6g}"):
    """Display a figure or table in a notebook so the book shows it under its thesis id.

    Parameters
    ----------
    obj : matplotlib.figure.Figure, pandas.DataFrame, str, pathlib.Path or None
        The figure (it is closed afterwards, so the inline backend does not show it twice), a
        table, a PNG/CSV file, or None to show the pipeline's own ``results/figures/<id>.png`` or
        ``results/tables/<id>.csv``. A figure is linked to the rule's full-size PNG and PDF when
        they exist.
    figure_id : str
        The id of FIGURES.md / ``data/figure_ids.yaml`` (``"fig_2_3"``, ``"table_d_1"``).
    caption : str
        The caption in our own words; the thesis number is prepended.

    Examples
    --------
    >>> from pedalrepro import figures
    >>> figures.show(figures.draw("fig_2_3"), "fig_2_3", "Right-leg COM.")  # doctest: +SKIP
    >>> figures.show(None, "fig_3_10", "Model HS, roll.")   # the rule's file  # doctest: +SKIP
    """
    import io

    import matplotlib.pyplot as plt
    import pandas as pd
    from IPython.display import display

    if not figure_id:
        raise ValueError("figures.show needs the figure id (e.g. 'fig_2_3')")
    if obj is None:
        fig_path, table_path = paths.figure(figure_id), paths.table(figure_id)
        obj = table_path if figure_id.startswith("table_") else fig_path
        if not Path(obj).exists():
            raise FileNotFoundError(f"{figure_id}: {obj} does not exist (run the pipeline)")
    bundle = {"text/plain": f"{thesis_label(figure_id)} ({figure_id})"}
    if isinstance(obj, (str, Path)) and str(obj).endswith(".csv"):
        obj = pd.read_csv(obj)
    if isinstance(obj, pd.DataFrame):
        table = obj.to_html(index=False, border=0, classes="table",
                            float_format=lambda x: float_format.format(x))
        bundle["text/html"] = figure_html(figure_id, table_html=table, caption=caption,
                                          link=paths.table(figure_id).exists())
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

        link = paths.figure(figure_id).exists() and paths.figure(figure_id, fmt="pdf").exists()
        bundle["text/html"] = figure_html(figure_id, png, caption=caption, link=link)
        bundle["image/png"] = base64.b64encode(png).decode("ascii")
    display(bundle, raw=True)


def plain_numbers_in_notebooks() -> bool:
    """Show numpy scalars as plain numbers (``3.15``, not ``np.float64(3.15)``) in IPython.

    numpy 2 changed the repr of its scalars; myst-nb's ``glue`` stores that repr as text/plain, and
    ``{glue:text}`x:.2f``` then cannot parse it (a warning, so the strict book build fails). Called
    on import of :mod:`pedalrepro.figures`, which every chapter notebook imports; a no-op outside
    IPython. Returns whether a kernel was found.
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


plain_numbers_in_notebooks()

from . import registry  # noqa: E402, F401  (the table of figures)
from .registry import draw  # noqa: E402, F401
