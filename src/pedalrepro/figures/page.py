"""Figures drawn for the page: the project's style, the legibility check and the writer.

A leaf module (matplotlib and :mod:`pedalrepro.paths` only) so that the figure registry and the
drawing modules can use it without importing the :mod:`pedalrepro.figures` package.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import matplotlib
import numpy as np

from .. import paths

__all__ = [
    "DATA_FILES", "style", "MAX_WIDTH_IN", "MIN_FONT_PT", "check_legible", "overlapping_colorbars",
    "whole_pixels", "png_from_draw", "save", "synthetic_stamp",
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


def whole_pixels(bbox, dpi: float):
    """``bbox`` (inches) grown to whole pixels at ``dpi``, so that the PNG is a crop of a
    draw at that dpi (:func:`png_from_draw`) and savefig's own render is the same."""
    import math

    from matplotlib.transforms import Bbox

    return Bbox([[math.floor(bbox.x0 * dpi) / dpi, math.floor(bbox.y0 * dpi) / dpi],
                 [math.ceil(bbox.x1 * dpi) / dpi, math.ceil(bbox.y1 * dpi) / dpi]])


def png_from_draw(fig: matplotlib.figure.Figure, tight_in, bbox_in, dpi: float,
                   path: Path) -> bool:
    """Write the PNG from the draw just made at ``dpi`` (Agg canvas), cropped to ``bbox_in``
    (whole pixels; where it reaches past the figure's edge, by the padding around the tight box
    ``tight_in``, filled with the figure's face colour, as savefig fills it), and written as
    savefig writes it (``matplotlib.image.imsave``, the same dpi and Software metadata).
    Returns False, writing nothing, when the canvas is not Agg's or an artist reaches outside
    the figure (the draw clipped it; savefig renders it). One render less per figure."""
    import matplotlib.colors
    import matplotlib.image
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(fig.canvas, FigureCanvasAgg):
        return False
    width, height = fig.canvas.get_width_height(physical=True)
    if (tight_in.x0 < 0 or tight_in.y0 < 0 or tight_in.x1 * dpi > width
            or tight_in.y1 * dpi > height):
        return False
    c0, c1 = round(bbox_in.x0 * dpi), round(bbox_in.x1 * dpi)
    r0, r1 = height - round(bbox_in.y1 * dpi), height - round(bbox_in.y0 * dpi)
    face = np.round(np.asarray(matplotlib.colors.to_rgba(fig.get_facecolor())) * 255)
    out = np.empty((r1 - r0, c1 - c0, 4), np.uint8)
    out[...] = face.astype(np.uint8)
    rgba = np.asarray(fig.canvas.buffer_rgba())
    rs, cs = slice(max(r0, 0), min(r1, height)), slice(max(c0, 0), min(c1, width))
    out[rs.start - r0:rs.stop - r0, cs.start - c0:cs.stop - c0] = rgba[rs, cs]
    matplotlib.image.imsave(path, out, format="png", dpi=dpi, metadata={
        "Software": f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/"})
    return True


def save(fig: matplotlib.figure.Figure, path: str | Path) -> Path:
    """Save ``fig`` to ``path`` (PNG) and its vector copy beside it (same stem, ``.pdf``), in
    the project's style, creating the folder; close the figure. Checks :func:`check_legible`
    first, then that no colour bar is drawn over another or over a plot
    (:func:`overlapping_colorbars`; so every figure a rule saves is checked, in every build), and
    that the PNG (bbox tight) is not wider than the content width plus 5 %.

    One layout and two renders for the three uses: the figure is drawn once at the PNG's dpi
    (its layout engine, e.g. constrained layout, runs there), the colour bars are checked on
    that draw, the tight bounding box is taken from it (padded by ``savefig.pad_inches`` and
    grown to whole pixels), the PNG is that draw cropped to the box (:func:`png_from_draw`),
    and the layout is then frozen (the layout engine removed) for the PDF. Before: five renders
    and three layouts per figure (``savefig(bbox_inches="tight")`` lays out and draws again
    for each file, and a placeholder layout engine draws once more). Constrained layout is not
    exactly idempotent (a second pass moves axes by ~2e-4 of the figure), so a PNG can differ
    from savefig's tight one by a pixel of placement and up to 2 px of size (the box grown to
    whole pixels; tests/figures/test_figures.py)."""
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
        tight_in = fig.get_tightbbox(renderer)
        bbox_in = whole_pixels(tight_in.padded(pad_in), dpi)
        path.parent.mkdir(parents=True, exist_ok=True)
        png_done = png_from_draw(fig, tight_in, bbox_in, dpi, path)
        # Frozen: no layout engine at all. ``set_layout_engine("none")`` would leave a
        # placeholder engine, and savefig lays out (draws, rendering disabled) a figure that
        # has one before each file: five draws instead of three.
        with matplotlib.rc_context({"figure.autolayout": False,
                                    "figure.constrained_layout.use": False}):
            fig.set_layout_engine(None)
        fig.set_dpi(screen_dpi)
        if not png_done:
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
