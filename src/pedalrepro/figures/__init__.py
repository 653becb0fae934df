"""One function per thesis figure: arrays/DataFrames in, a matplotlib ``Figure`` out.

The same functions serve the Snakemake rules (which save ``results/figures/<id>.png``) and the
notebooks (which show them). Submodules by thesis part: ``section2``, ``linear``, ``nonlinear``,
``validation``. Use :func:`style` so every figure looks alike, and :func:`save` to write one.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import matplotlib

from .. import paths

#: Read through ``paths.STYLE`` (see pedalrepro.dependencies).
DATA_FILES: tuple[str, ...] = ("src/pedalrepro/pedalrepro.mplstyle",)


@contextmanager
def style():
    """Context manager applying the project's matplotlib style (``pedalrepro.mplstyle``)."""
    with matplotlib.style.context(str(paths.STYLE)):
        yield


def save(fig: matplotlib.figure.Figure, path: str | Path) -> Path:
    """Save ``fig`` to ``path`` (PNG), creating the folder, and close it."""
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def synthetic_stamp(fig: matplotlib.figure.Figure, reason: str = "") -> None:
    """Write a visible SYNTHETIC label on a figure built from the synthetic stand-in data."""
    text = "SYNTHETIC DATA (stand-in for the treadmill data)"
    if reason:
        text += f": {reason}"
    fig.text(0.5, 0.995, text, ha="center", va="top", color="crimson", fontsize=9,
             fontweight="bold")


def thesis_label(figure_id: str) -> str:
    """Thesis number of a figure/table id: ``"fig_2_3"`` -> ``"Figure 2.3"``, ``"table_d_1"`` ->
    ``"Table D.1"``."""
    kind, _, number = figure_id.partition("_")
    if kind not in ("fig", "table") or not number:
        raise ValueError(f"figure id {figure_id!r} is not fig_<chapter>_<n> or table_<chapter>_<n>")
    parts = [p.upper() if p.isalpha() else p for p in number.split("_")]
    return ("Table " if kind == "table" else "Figure ") + ".".join(parts)


def figure_html(figure_id: str, png: bytes | None = None, *, table_html: str | None = None,
                caption: str = "") -> str:
    """The HTML element the book shows for one figure or table id (see CONTRIBUTING.md,
    "Figures in the book"): ``<figure class="pedalrepro-figure" id="pedalrepro-<id>"
    data-figure-id="<id>">`` holding an ``<img alt="<id> ...">`` (PNG embedded as a data URI, so
    the page needs no other file) or an HTML table, and a caption led by the thesis number."""
    import base64
    import html

    label = thesis_label(figure_id)
    cap = f"<strong>{label} of the thesis</strong> (<code>{figure_id}</code>)"
    if caption:
        cap += ". " + html.escape(caption)
    if png is not None:
        data = base64.b64encode(png).decode("ascii")
        body = (f'<img src="data:image/png;base64,{data}" alt="{figure_id}: {label}" '
                'style="max-width:100%;height:auto">')
    elif table_html is not None:
        body = f'<div class="pedalrepro-table" style="overflow-x:auto">{table_html}</div>'
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
        ``results/tables/<id>.csv``.
    figure_id : str
        The id of FIGURES.md / ``data/figure_ids.yaml`` (``"fig_2_3"``, ``"table_d_1"``).
    caption : str
        The caption in our own words; the thesis number is prepended.

    Examples
    --------
    >>> from pedalrepro import figures
    >>> with figures.style():                                    # doctest: +SKIP
    ...     fig = figures.section2.fig_2_3(kinematics)
    >>> figures.show(fig, "fig_2_3", "Right-leg COM at 60 rpm.")   # doctest: +SKIP
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
        bundle["text/html"] = figure_html(figure_id, table_html=table, caption=caption)
    else:
        if isinstance(obj, (str, Path)):
            png = Path(obj).read_bytes()
        else:
            buf = io.BytesIO()
            obj.savefig(buf, format="png")
            plt.close(obj)
            png = buf.getvalue()
        import base64

        bundle["text/html"] = figure_html(figure_id, png, caption=caption)
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
