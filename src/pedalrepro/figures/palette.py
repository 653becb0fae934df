"""One style table for every chapter: model colours, method line styles, map levels.

Chapter 3 (linear and non-linear methods) and chapter 4 (validation) draw a model or a method
with the same colour and line style, so a reader can follow HS, CF, HR and CR (and LA, LN, NT,
NP, PS) from figure to figure.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "MODEL_COLOURS", "METHOD_STYLE", "METHOD_LABEL", "MEASURED_COLOUR", "CAM_COLOUR", "WEAVE_STYLE",
    "STABLE_STYLE", "RD_TICKS_PERCENT", "RD_LOG_LEVELS_PERCENT", "model_colour",
]

#: Colour of each model (Appendix B models, the benchmark) in every chapter.
MODEL_COLOURS: dict[str, str] = {"HS": "#1f77b4", "CF": "#d62728", "HR": "#2ca02c",
                                 "CR": "#ff7f0e", "benchmark": "#7f7f7f"}

#: Line style of each time-solution method (Sec 3.1.2): LA solid and widest underneath, the
#: others drawn on top of it thinner and dashed, so that none hides another (PS is drawn last,
#: thinnest, dotted black).
METHOD_STYLE: dict[str, dict] = {
    "LA": dict(color="#1f77b4", lw=2.2, ls="-", alpha=0.55, zorder=2),
    "LN": dict(color="#ff7f0e", lw=1.2, ls=(0, (4, 2)), zorder=3),
    "NT": dict(color="#2ca02c", lw=1.1, ls="-.", zorder=4),
    "NP": dict(color="#d62728", lw=1.1, ls=(0, (1, 1)), zorder=5),
    "PS": dict(color="k", lw=0.8, ls=(0, (5, 3)), zorder=6),
    "LA T(w)": dict(color="#9467bd", lw=0.9, ls="-", zorder=3),
    "NP no window": dict(color="#d62728", lw=0.7, ls="-", alpha=0.45, zorder=1),
    "LA no window": dict(color="0.55", lw=0.7, ls="-", zorder=1),
}
METHOD_LABEL: dict[str, str] = {
    "LA": "LA linear analytic", "LN": "LN linear numerical",
    "NT": "NT non-linear, torques", "NP": "NP non-linear, pedalling legs",
    "PS": "PS particular solution", "LA T(w)": "LA, T($\\omega$) only",
    "NP no window": "NP, no window", "LA no window": "LA, no window",
}

#: Colour of measured data (chapter 4) beside a model drawn in its model colour.
MEASURED_COLOUR = "k"
#: The CAM isoline (conservation of angular momentum, Sec 3.1.2.3).
CAM_COLOUR = "#7b0c2e"
#: Weave imaginary part (dashed) and the self-stable range (solid vertical lines) on the maps.
WEAVE_STYLE = dict(color="w", lw=1.0, ls="--")
STABLE_STYLE = dict(color="w", lw=1.0, ls="-")

#: Relative-difference levels (%) the thesis labels on its RD colour bars (Sec 3.2).
RD_TICKS_PERCENT: tuple[float, ...] = (0.1, 1, 2.5, 5, 10, 25, 100)
#: Filled-contour levels of the RD maps: the labelled levels plus the far ends.
RD_LOG_LEVELS_PERCENT = np.array([1e-6, 0.1, 1, 2.5, 5, 10, 25, 100, 1e6])


def model_colour(model: str) -> str:
    """Colour of ``model``; grey for a model outside the table."""
    return MODEL_COLOURS.get(model, "#555555")
