"""Drawing functions named after the figures they draw: arrays/DataFrames in, a matplotlib
``Figure`` out.

Every figure is registered in ONE table, :mod:`pedalrepro.figures.registry` (id -> drawing
function and the files it reads), which the Snakemake rules (``rules/figures.smk``: inputs,
outputs, :func:`registry.write`) and the notebooks (:func:`draw`, ``show(None, id)``) both use.
A function the registry calls for one id is named that id (``section2.fig_2_3``,
``linear.fig_3_8``, ``validation.real_run_panel``); one it calls for several ids is named
``figs_<topic>`` (``linear.figs_ps_time``) and lists every id it draws in its docstring's first
paragraph; no other function is named ``fig_...``/``figs_...``
(``tests/figures/test_figure_names.py``). Drawing functions by thesis part: ``section2``,
``linear``, ``nonlinear``, ``validation``, and ``periodic`` beyond the thesis; model colours and
method line styles in ``palette``.

Figures are drawn for the page: at most :data:`MAX_WIDTH_IN` (the book's 672 px content width)
wide, with no text below :data:`MIN_FONT_PT`; :func:`save` refuses a figure that is not, and
writes a PNG and a PDF (vector) beside it; the book links each figure to both. The book's HTML
helpers (``show``, ``figure_html``) are in :mod:`pedalrepro.book`, re-exported here.
"""

from __future__ import annotations

# The book's HTML helpers live in pedalrepro.book; re-exported here for the notebooks that call
# them as figures.show(...) (importing this package changes nothing in IPython: a notebook asks
# with book.setup()).
from ..book import (  # noqa: E402, F401
    BEYOND_THESIS,
    BOOK_FIGURES_HREF,
    BOOK_TABLES_HREF,
    figure_html,
    show,
    thesis_label,
)
from . import registry  # noqa: E402, F401  (the table of figures)
from .page import (  # noqa: F401  (the package's public names)
    MAX_WIDTH_IN,
    MIN_FONT_PT,
    check_legible,
    save,
    style,
    synthetic_stamp,
)
from .registry import draw  # noqa: E402, F401

__all__ = [
    "BEYOND_THESIS", "BOOK_FIGURES_HREF", "BOOK_TABLES_HREF", "MAX_WIDTH_IN", "MIN_FONT_PT",
    "check_legible", "draw", "figure_html", "registry", "save", "show", "style", "synthetic_stamp",
    "thesis_label",
]
