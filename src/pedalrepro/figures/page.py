"""Figures drawn for the page: the project's style, the legibility check and the writer.

A leaf module (matplotlib and :mod:`pedalrepro.paths` only) so that the figure registry and the
drawing modules can use it without importing the :mod:`pedalrepro.figures` package.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import matplotlib

from .. import paths

__all__ = [
    "DATA_FILES", "style", "MAX_WIDTH_IN", "MIN_FONT_PT", "check_legible", "overlapping_colorbars",
    "save", "synthetic_stamp",
]

#: Read through ``paths.STYLE`` (see pedalrepro.dependencies).
DATA_FILES: tuple[str, ...] = ("src/pedalrepro/pedalrepro.mplstyle",)


@contextmanager
def style():
    """Context manager applying the project's matplotlib style (``pedalrepro.mplstyle``)."""
    import matplotlib.style

    with matplotlib.style.context(str(paths.STYLE)):
        yield


#: Widest figure (inches): the book's content width, 672 px at 96 px per inch.
MAX_WIDTH_IN = 7.0
#: Smallest text (points at the figure's own size, which is its display size in the book).
MIN_FONT_PT = 8.0


def check_legible(fig: matplotlib.figure.Figure, name: str = "figure") -> None:
    """Raise ValueError if ``fig`` is wider than :data:`MAX_WIDTH_IN` or shows text smaller
    than :data:`MIN_FONT_PT` (figures are drawn for the page: split dense figures into rows
    instead)."""
    from matplotlib.text import Text

    width = float(fig.get_size_inches()[0])
    if width > MAX_WIDTH_IN + 1e-9:
        raise ValueError(f"{name}: {width:.2f} in wide, more than the book's {MAX_WIDTH_IN} in "
                         "content width (draw it narrower, in rows)")
    small = sorted({(round(t.get_fontsize(), 1), t.get_text()[:30]) for t in fig.findobj(Text)
                    if t.get_visible() and t.get_text().strip()
                    and t.get_fontsize() < MIN_FONT_PT - 1e-9})
    if small:
        raise ValueError(f"{name}: text below {MIN_FONT_PT} pt: {small[:5]}")


def overlapping_colorbars(fig: matplotlib.figure.Figure, renderer=None) -> list[str]:
    """Colour bars drawn over another colour bar or over a plot (two colour bars of
    the periodic maps were drawn on top of each other): the drawn bounding boxes (display
    units, after a draw) of each colour bar axes, its ticks and label included, against those of
    every other colour bar and the frame of every other axes. Returns one line per overlap
    (empty: none; a figure without colour bars is not drawn). ``renderer``: the renderer of a
    draw just made (:func:`save` draws once for this check and the files), else one is made."""
    axes = [ax for ax in fig.axes if ax.get_visible()]
    bars = [ax for ax in axes if getattr(ax, "_colorbar", None) is not None]
    if not bars:
        return []
    if renderer is None:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()

    def name(ax) -> str:
        label = ax.get_ylabel() or ax.get_xlabel() or ax.get_title() or "unlabelled"
        return f"{'colour bar' if ax in bars else 'axes'} {label!r}"

    found = []
    for i, bar in enumerate(bars):
        tight = bar.get_tightbbox(renderer)
        frame = bar.get_window_extent(renderer)
        for other in axes:
            if other is bar or (other in bars and bars.index(other) < i):
                continue
            box = other.get_tightbbox(renderer) if other in bars else \
                other.get_window_extent(renderer)
            mine = tight if other in bars else frame
            w = min(mine.x1, box.x1) - max(mine.x0, box.x0)
            h = min(mine.y1, box.y1) - max(mine.y0, box.y0)
            if w > 1.0 and h > 1.0:  # more than a pixel in both directions
                found.append(f"{name(bar)} overlaps {name(other)} ({w:.0f} x {h:.0f} px)")
    return found


def save(fig: matplotlib.figure.Figure, path: str | Path) -> Path:
    """Save ``fig`` to ``path`` (PNG) and its vector copy beside it (same stem, ``.pdf``), in
    the project's style, creating the folder; close the figure. Checks :func:`check_legible`
    first, then that no colour bar is drawn over another or over a plot
    (:func:`overlapping_colorbars`; so every figure a rule saves is checked, in every build), and
    that the PNG (bbox tight) is not wider than the content width plus 5 %.

    One layout for the three uses: the figure is drawn once at the PNG's dpi (its layout engine,
    e.g. constrained layout, runs there), the colour bars are checked on that draw, the tight
    bounding box is taken from it (padded by ``savefig.pad_inches``), and the layout is then
    frozen for the two files (the layout engine removed). ``savefig(bbox_inches="tight")``
    would lay out and draw the figure again for each file: five draws and three layouts per
    figure instead of three and one (the saves of the 16 linear-time figures: 45-48 s -> 34-35
    s, this machine). Constrained layout is not exactly idempotent (a second pass moves axes
    by ~2e-4 of the figure), so a PNG can differ from the old path's by a pixel of placement
    or size (tests/figures/test_figures.py)."""
    import struct

    import matplotlib.pyplot as plt

    path = Path(path)
    check_legible(fig, path.stem)
    with style():
        dpi = float(matplotlib.rcParams["savefig.dpi"])
        pad_in = float(matplotlib.rcParams["savefig.pad_inches"])
        screen_dpi = fig.dpi
        fig.set_dpi(dpi)
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        overlaps = overlapping_colorbars(fig, renderer)
        if overlaps:
            plt.close(fig)
            raise ValueError(f"{path.name}: " + "; ".join(overlaps))
        bbox_in = fig.get_tightbbox(renderer).padded(pad_in)
        # Frozen: no layout engine at all. ``set_layout_engine("none")`` would leave a
        # placeholder engine, and savefig lays out (draws, rendering disabled) a figure that
        # has one before each file: five draws instead of three.
        with matplotlib.rc_context({"figure.autolayout": False,
                                    "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)
        fig.set_dpi(screen_dpi)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, bbox_inches=bbox_in)
        fig.savefig(path.with_suffix(".pdf"), bbox_inches=bbox_in)
    plt.close(fig)
    width_px = struct.unpack(">I", path.read_bytes()[16:20])[0]
    if width_px > 1.05 * MAX_WIDTH_IN * dpi:
        raise ValueError(f"{path}: {width_px} px wide at {dpi:g} dpi, more than "
                         f"{MAX_WIDTH_IN} in (something sticks out of the figure)")
    return path


def synthetic_stamp(fig: matplotlib.figure.Figure, reason: str = "") -> None:
    """Write a visible SYNTHETIC label on a figure built from the synthetic stand-in data."""
    import textwrap

    text = "SYNTHETIC DATA (stand-in for the treadmill data)"
    if reason:
        text += f": {reason}"
    text = textwrap.fill(text, 80)  # inside the figure's width at 9 pt bold
    if fig.get_suptitle():
        fig.text(0.5, 0.995, text, ha="center", va="top", color="crimson", fontsize=9,
                 fontweight="bold")
    else:  # a suptitle: constrained layout keeps room for it
        fig.suptitle(text, color="crimson", fontsize=9, fontweight="bold")
