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
