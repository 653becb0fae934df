"""Figures of the linear open-loop response (thesis Sec 3, Appendices F, G, H).

Every function takes loaded result arrays (dicts of numpy arrays, as ``dict(np.load(npz))``) and
returns a matplotlib ``Figure``; nothing here computes a sweep. Which files each figure reads is
registered in :mod:`pedalrepro.figures.registry` (the one table the rules and the notebooks use).

Figures are drawn for the book's 7 in (672 px) content width with text of at least 8 pt. Axes
follow the thesis: forward speed (m/s) horizontally, cadence (rad/s) vertically. Colours and line
styles come from :mod:`pedalrepro.figures.palette`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm
from matplotlib.figure import Figure

from .. import gears, spectral
from .palette import (
    CAM_COLOUR,
    METHOD_LABEL,
    METHOD_STYLE,
    RD_LOG_LEVELS_PERCENT,
    RD_TICKS_PERCENT,
    STABLE_STYLE,
    WEAVE_STYLE,
    model_colour,
)

__all__ = [
    "Arrays", "ALL_TIME_METHODS", "AMP_LEVELS", "RD_LEVELS_PERCENT", "WIDTH_IN",
    "zoom_window", "eigen_panel", "figs_eigenvalues", "fig_3_8", "figs_ps_time",
    "figs_series_time", "figs_fft", "figs_series_fft", "fig_3_30", "figs_neglected_momenta",
    "fig_3_35", "figs_gear_sections", "fig_g_7", "rd_norm", "rd_colorbar",
    "rd_map", "fig_3_37", "fig_3_38", "figs_rd_points",
]

Arrays = Mapping[str, np.ndarray]

#: Every time-solution method of the thesis (Sec 3.1.2); the linear part makes LA and LN.
ALL_TIME_METHODS: tuple[str, ...] = ("LA", "LN", "NT", "NP")
AMP_LEVELS = np.linspace(0.0, 0.04, 9)
#: Linear RD levels (percent) for the parameter comparisons of evaluation points 4-6.
RD_LEVELS_PERCENT = np.array([0, 5, 10, 25, 50, 75, 100, 150, 200])
#: Book content width (inches at 96 px per inch: 672 px).
WIDTH_IN = 7.0


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------

def _missing_note(fig: Figure, present: Sequence[str], wanted: Sequence[str] = ALL_TIME_METHODS,
                  what: str = "time solutions not computed in this build") -> list[str]:
    missing = [m for m in wanted if m not in present]
    if missing:
        fig.text(0.01, 0.0, "not available here: " + ", ".join(missing) + f" ({what})",
                 fontsize=8, color="0.3", ha="left", va="top")
    return missing


def _stable_ranges(eig: Arrays) -> np.ndarray:
    return np.asarray(eig["stable_ranges_m_s"]).reshape(-1, 2)


def _decorate(ax, eig: Arrays | None, y_max: float, *, weave: bool = True) -> None:
    """Weave imaginary part (dashed) and the self-stable range (two solid vertical lines): the
    map's colours stay as they are inside the range."""
    if eig is None:
        return
    if weave:
        v, f = eig["speed_m_s"], eig["weave_frequency_rad_s"]
        f = np.where(f > 0, f, np.nan)
        ax.plot(v, f, **{**WEAVE_STYLE, "color": "k", "lw": WEAVE_STYLE["lw"] + 1.0, "ls": "-",
                         "alpha": 0.35})
        ax.plot(v, f, **WEAVE_STYLE, label="Im(weave)")
    for lo, hi in _stable_ranges(eig):
        for x in (lo, hi):
            ax.axvline(x, **STABLE_STYLE)
    ax.set_ylim(0, y_max)


def _rpm_axis(ax) -> None:
    """Secondary cadence axis in rpm on the right (rad/s on the left)."""
    sec = ax.secondary_yaxis("right", functions=(lambda w: w * 30 / np.pi,
                                                 lambda r: r * np.pi / 30))
    sec.set_ylabel("cadence (rpm)")


def _ps_contour(ax, ps: Arrays, coord: str, eig: Arrays | None = None, *, cam: bool = True,
                levels=AMP_LEVELS, colorbar: bool = True, cam_band: float | None = None):
    v, w = ps["speed_m_s"], ps["omega_rad_s"]
    amp = ps[f"{coord}_amp_rad"]
    cs = ax.contourf(v, w, amp.T, levels=levels, extend="max", cmap="viridis")
    if cam:
        level = float(ps[f"cam_{coord}_rad"])
        if cam_band:
            ax.contourf(v, w, amp.T, levels=[level * (1 - cam_band), level * (1 + cam_band)],
                        colors=[CAM_COLOUR], alpha=0.3)
        ax.contour(v, w, amp.T, levels=[level], colors=[CAM_COLOUR], linewidths=1.8)
    _decorate(ax, eig, w.max())
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("cadence $\\omega$ (rad/s)")
    if colorbar:
        ax.figure.colorbar(cs, ax=ax, label=f"{coord} amplitude (rad)")
    return cs


def _label_points(ax, speeds, omegas, color="w") -> None:
    for i, (a, b) in enumerate(zip(speeds, omegas, strict=True)):
        ax.plot(a, b, "o", ms=11, mfc="none", mec=color)
        ax.text(a, b, str(i + 1), color=color, ha="center", va="center", fontsize=8)


def _ps_time(ps: Arrays, coord: str, speed: float, omega: float, t: np.ndarray) -> np.ndarray:
    """The periodic particular solution in time at (speed, omega) by nearest PS grid point."""
    i = int(np.argmin(np.abs(ps["speed_m_s"] - speed)))
    j = int(np.argmin(np.abs(ps["omega_rad_s"] - omega)))
    q = ps[coord][i, j]
    return np.real(np.exp(1j * np.multiply.outer(t, ps["n"] * omega)) @ q)


def _last_finite_time(t: np.ndarray, y: np.ndarray) -> float:
    ok = np.isfinite(y)
    return float(t[ok][-1]) if ok.any() else float(t[0])


def zoom_window(t: np.ndarray, curves: Sequence[np.ndarray], omega_rad_s: float,
                min_s: float = 4.0, max_s: float = 15.0, periods: float = 5.0
                ) -> tuple[float, float]:
    """The zoom of a time panel: the last ``periods`` cadence periods (``min_s``-``max_s``
    seconds) before the earliest end of the curves (a fall ends a curve), so that every method
    is visible in it."""
    end = min(_last_finite_time(t, y) for y in curves) if curves else float(t[-1])
    length = float(np.clip(periods * 2 * np.pi / max(omega_rad_s, 1e-9), min_s, max_s))
    return max(float(t[0]), end - length), end


def _sym_limits(ax, curves, lo: float, hi: float, t: np.ndarray) -> None:
    sel = (t >= lo) & (t <= hi)
    vals = [np.abs(y[sel][np.isfinite(y[sel])]) for y in curves]
    top = max([float(v.max()) for v in vals if v.size] + [1e-6])
    ax.set_ylim(-1.1 * top, 1.1 * top)


def _time_rows_fig(n_rows: int = 6, map_height: float = 2.8, row_height: float = 1.25):
    """A figure at the book width: a map on top, then ``n_rows`` rows of (whole run, zoom)."""
    fig = plt.figure(figsize=(WIDTH_IN, map_height + 0.75 + n_rows * row_height),
                     layout="constrained")
    gs = fig.add_gridspec(n_rows + 2, 2, height_ratios=[map_height, 0.5] + [row_height] * n_rows,
                          width_ratios=[1, 2.3])
    ax_map = fig.add_subplot(gs[0, :])
    ax_leg = fig.add_subplot(gs[1, :])
    ax_leg.axis("off")
    rows = [(fig.add_subplot(gs[2 + k, 0]), fig.add_subplot(gs[2 + k, 1]))
            for k in range(n_rows)]
    return fig, ax_map, ax_leg, rows


def _legend_row(ax_leg, handles_by_label: dict) -> None:
    n = len(handles_by_label)
    ax_leg.legend(list(handles_by_label.values()), list(handles_by_label), loc="center",
                  ncols=n if n <= 3 else (n + 1) // 2, frameon=False, fontsize=8,
                  columnspacing=1.2, handlelength=2.5)


def _time_panels(rows, t: np.ndarray, curves_per_point: list[dict[str, np.ndarray]],
                 speeds, omegas, coord: str, min_zoom_s: float = 4.0) -> dict:
    """Whole run (left, small) and a zoom on its last periods (right) for each point; returns
    the legend handles by label."""
    handles: dict = {}
    for k, ((ax_all, ax_zoom), curves) in enumerate(zip(rows, curves_per_point, strict=True)):
        for name, y in curves.items():
            style = METHOD_STYLE[name]
            ax_all.plot(t, y, **{**style, "lw": min(style["lw"], 0.8)}, label=name,
                        rasterized=True)  # long runs: a small PDF
            (h,) = ax_zoom.plot(t, y, **style, label=name)
            handles.setdefault(METHOD_LABEL[name], h)
        lo, hi = zoom_window(t, [y for n, y in curves.items() if n != "PS"], omegas[k],
                             min_s=min_zoom_s)
        ax_zoom.set_xlim(lo, hi)
        _sym_limits(ax_zoom, list(curves.values()), lo, hi, t)
        ax_all.axvspan(lo, hi, color="0.85", zorder=0, lw=0)
        ax_all.set_xlim(t[0], t[-1])
        ax_all.set_ylabel(f"{k + 1}: {coord} (rad)")
        ax_zoom.set_title(f"{k + 1}: v = {speeds[k]:.1f} m/s, $\\omega$ = {omegas[k]:.1f} rad/s"
                          f" (zoom {hi - lo:.0f} s)", fontsize=8, loc="left")
        if k == 0:
            ax_all.set_title("whole run (grey: zoom)", fontsize=8, loc="left")
        if k == len(rows) - 1:
            ax_all.set_xlabel("t (s)")
            ax_zoom.set_xlabel("t (s)")
    return handles


# --------------------------------------------------------------------------------------------
# eigenvalues, gears
# --------------------------------------------------------------------------------------------

def eigen_panel(ax, e: Arrays, title: str) -> None:
    """One eigenvalue-vs-speed panel (``linear_eigen`` npz format): Re by mode, Im weave.

    Real parts solid, coloured by mode; the weave imaginary part dashed; self-stable range
    between two vertical lines (lightly shaded).
    """
    colors = {"weave": "C0", "capsize": "C1", "caster": "C2"}
    v, lam, names = e["speed_m_s"], e["eigenvalues"], [str(s) for s in e["names"]]
    done = set()
    for j, name in enumerate(names):
        ax.plot(v, lam[:, j].real, color=colors[name], label=None if name in done
                else f"Re, {name}")
        done.add(name)
    ax.plot(v, e["weave_frequency_rad_s"], "C0--", label="Im, weave")
    for lo, hi in _stable_ranges(e):
        ax.axvspan(lo, hi, color="0.9", zorder=0, label="self-stable")
        ax.axvline(lo, color="0.4", lw=0.8)
        ax.axvline(hi, color="0.4", lw=0.8)
    ax.axhline(0, color="k", lw=0.6)
    ax.set_ylim(-10, 10)
    ax.set_title(title)
    ax.set_xlabel("v (m/s)")
    ax.set_ylabel("eigenvalue (1/s)")


def figs_eigenvalues(eigen: Mapping[str, Arrays], models: Sequence[str]) -> Figure:
    """Eigenvalues vs speed, one panel per model: ``fig_3_6`` (Fig 3.6, the benchmark) and
    ``fig_3_9`` (Fig 3.9, HS, CF, HR, CR)."""
    n = len(models)
    fig, axes = plt.subplots(1 if n == 1 else 2, 1 if n == 1 else 2, squeeze=False,
                             figsize=(WIDTH_IN, 4.2) if n == 1 else (WIDTH_IN, 6.2),
                             sharex=True, layout="constrained")
    for ax, m in zip(axes.flat, models, strict=False):
        eigen_panel(ax, eigen[m], m)
    axes.flat[0].legend(loc="lower left", fontsize=8)
    return fig


def fig_3_8(grid: Arrays) -> Figure:
    """Fig 3.8: the speed-cadence grid with gear-ratio lines and the 'normal cycling' ellipse
    (``grid``: :func:`pedalrepro.figdata.gear_grid`)."""
    speed_m_s, omega_rad_s = grid["speed_m_s"], grid["omega_rad_s"]
    radius = float(grid["wheel_radius_m"])
    fig, ax = plt.subplots(figsize=(WIDTH_IN, 4.4), layout="constrained")
    vv, ww = np.meshgrid(speed_m_s, omega_rad_s)
    ax.plot(vv.ravel(), ww.ravel(), ".", color="0.75", ms=1.5)
    w_line = np.linspace(0, omega_rad_s.max(), 50)
    for gr in grid["gear_ratios"]:
        v_line = gears.speed_m_s(gr, w_line, radius)
        keep = v_line <= speed_m_s.max()
        ax.plot(v_line[keep], w_line[keep], label=f"GR {gr:g}")
    ax.plot(grid["ellipse_speed_m_s"], grid["ellipse_omega_rad_s"], "k-", lw=1.5,
            label="normal cycling")
    ref = grid["reference"]
    ax.plot(ref[0], ref[1], "k*", ms=9, label="reference 60 rpm, 5 m/s")
    ax.set_xlim(0, speed_m_s.max())
    ax.set_ylim(0, omega_rad_s.max())
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("cadence $\\omega$ (rad/s)")
    _rpm_axis(ax)
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(f"wheel radius {radius:.3f} m")
    return fig


# --------------------------------------------------------------------------------------------
# particular solution + time solutions (Fig 3.10-3.19, G.1-G.6)
# --------------------------------------------------------------------------------------------

def figs_ps_time(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str, coord: str,
                single_harmonic: bool = False) -> Figure:
    """PS amplitude map (top) and time solutions at six points: Figs 3.10-3.17 and G.1-G.6,
    ``fig_3_10``, ``fig_3_11``, ``fig_3_12``, ``fig_3_13``, ``fig_3_14``, ``fig_3_15``,
    ``fig_3_16``, ``fig_3_17``, ``fig_g_1``, ``fig_g_2``, ``fig_g_3``, ``fig_g_4``, ``fig_g_5``,
    ``fig_g_6``.

    Top: particular-solution amplitude at the cadence, the CAM isoline (burgundy), the weave
    imaginary part (dashed) and the self-stable range (vertical lines), with the six numbered
    points. Below, one row per point: the whole run (left, small; grey band = the zoom) and a
    zoom on its last cadence periods, or up to the first fall (right), every method present and
    the particular solution. ``single_harmonic`` adds LA driven by the cadence harmonic only
    (Appendix G).
    """
    fig, ax_map, ax_leg, rows = _time_rows_fig()
    _ps_contour(ax_map, ps, coord, eig)
    _rpm_axis(ax_map)
    ax_map.set_title(f"model {model}: {coord}, particular solution and time solutions",
                     fontsize=9)
    present = [m for m in ALL_TIME_METHODS if m in time]
    if present:
        ref = time[present[0]]
        sv, sw = ref["example_speed_m_s"], ref["example_omega_rad_s"]
        _label_points(ax_map, sv, sw)
        t = ref["example_t_s"]
        curves = []
        for k in range(len(rows)):
            c = {m: time[m][f"example_{coord}_rad"][k] for m in present}
            if single_harmonic and "LA" in time and f"example_{coord}_h1_rad" in time["LA"]:
                c["LA T(w)"] = time["LA"][f"example_{coord}_h1_rad"][k]
            c["PS"] = _ps_time(ps, coord, sv[k], sw[k], t)
            curves.append(c)
        _legend_row(ax_leg, _time_panels(rows, t, curves, sv, sw, coord))
    _missing_note(fig, present)
    return fig


def figs_series_time(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str,
                    coord: str) -> Figure:
    """Time solutions at one speed and six cadences: ``fig_3_18`` (Fig 3.18, HS) and
    ``fig_3_19`` (Fig 3.19, CR).

    The zoom is at least 8 s long, so that the weave period (about 3 s, Sec 3.2.2) shows."""
    fig, ax_map, ax_leg, rows = _time_rows_fig()
    _ps_contour(ax_map, ps, coord, eig)
    _rpm_axis(ax_map)
    ax_map.set_title(f"model {model}: {coord}, one speed, six cadences", fontsize=9)
    present = [m for m in ALL_TIME_METHODS if m in time and "series_speed_m_s" in time[m]]
    if present:
        ref = time[present[0]]
        sv, sw = ref["series_speed_m_s"], ref["series_omega_rad_s"]
        _label_points(ax_map, sv, sw)
        t = ref["example_t_s"]
        curves = [{**{m: time[m][f"series_{coord}_rad"][k] for m in present},
                   "PS": _ps_time(ps, coord, sv[k], sw[k], t)} for k in range(len(rows))]
        _legend_row(ax_leg, _time_panels(rows, t, curves, sv, sw, coord, min_zoom_s=8.0))
    _missing_note(fig, present, what="one-speed series not in this build's time files")
    return fig


# --------------------------------------------------------------------------------------------
# frequency domain (Fig 3.20-3.29)
# --------------------------------------------------------------------------------------------

def _spectrum_panel(ax, d: Arrays, key: str, k: int, fs: float, style: dict, label: str,
                    windowed: bool = True):
    if key not in d:  # e.g. a method file without the one-speed series of Fig 3.28/3.29
        return None
    x = d[key][k]
    x = x[np.isfinite(x)]
    if len(x) < 8:
        return None
    f, a = spectral.spectrum(x, fs, "hann" if windowed else None)
    (h,) = ax.semilogy(2 * np.pi * f, np.maximum(a, 1e-12), label=label, **style)
    return h


def figs_fft(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str, coord: str,
            series: bool = False) -> Figure:
    """Hann-DFT cadence amplitude vs PS (top), spectra at six points (below): Figs 3.20-3.27,
    ``fig_3_20``, ``fig_3_21``, ``fig_3_22``, ``fig_3_23``, ``fig_3_24``, ``fig_3_25``,
    ``fig_3_26``, ``fig_3_27`` (the one-speed series of Figs 3.28/3.29 through
    :func:`figs_series_fft`).

    Top: the Hann-windowed DFT amplitude of the LA time solutions on the time grid (colours,
    same scale as the PS) with the PS amplitude as black contour lines. Below: spectra of the
    runs of every method with the Hann window, and of LA (and, for the one-speed series of
    Figs 3.28/3.29, of NP as the thesis) without it; the PS amplitude as a black dot at the
    cadence.
    """
    prefix = "series" if series else "example"
    fig = plt.figure(figsize=(WIDTH_IN, 9.6), layout="constrained")
    gs = fig.add_gridspec(5, 2, height_ratios=[2.8, 0.5, 1.6, 1.6, 1.6])
    ax_map = fig.add_subplot(gs[0, :])
    ax_leg = fig.add_subplot(gs[1, :])
    ax_leg.axis("off")
    axes = [fig.add_subplot(gs[2 + i, j]) for i in range(3) for j in range(2)]
    present = [m for m in ALL_TIME_METHODS if m in time and f"{prefix}_{coord}_rad" in time[m]]
    v, w = ps["speed_m_s"], ps["omega_rad_s"]
    grid_methods = [m for m in ALL_TIME_METHODS if m in time]
    if grid_methods:
        d0 = time[grid_methods[0]]
        cs = ax_map.pcolormesh(d0["speed_m_s"], d0["omega_rad_s"],
                               d0[f"{coord}_amp_rad"].T, vmin=0, vmax=AMP_LEVELS[-1],
                               shading="nearest", cmap="viridis")
        fig.colorbar(cs, ax=ax_map, label=f"{grid_methods[0]} Hann-DFT\n{coord} amplitude (rad)")
    ax_map.contour(v, w, ps[f"{coord}_amp_rad"].T, levels=AMP_LEVELS[1:], colors="k",
                   linewidths=0.5)
    _decorate(ax_map, eig, w.max())
    ax_map.set_xlabel("forward speed v (m/s)")
    ax_map.set_ylabel("cadence $\\omega$ (rad/s)")
    ax_map.set_title(f"model {model}: {coord}, frequency domain", fontsize=9)
    handles: dict = {}
    if present:
        ref = time[present[0]]
        sv, sw = ref[f"{prefix}_speed_m_s"], ref[f"{prefix}_omega_rad_s"]
        _label_points(ax_map, sv, sw)
        fs = float(ref["sample_rate_hz"]) if "sample_rate_hz" in ref else 1.0 / float(
            np.diff(ref["example_t_s"][:2])[0])
        for k, ax in enumerate(axes):
            drawn = []
            for m in present:
                drawn.append((METHOD_LABEL[m], _spectrum_panel(
                    ax, time[m], f"{prefix}_{coord}_rad", k, fs, METHOD_STYLE[m], m)))
            unwindowed = ["LA"] + (["NP"] if series else [])
            for m in unwindowed:
                if m in present:
                    name = f"{m} no window"
                    drawn.append((METHOD_LABEL[name], _spectrum_panel(
                        ax, time[m], f"{prefix}_{coord}_rad", k, fs, METHOD_STYLE[name], name,
                        windowed=False)))
            i = int(np.argmin(np.abs(v - sv[k])))
            j = int(np.argmin(np.abs(w - sw[k])))
            (h,) = ax.plot(sw[k], ps[f"{coord}_amp_rad"][i, j], "ko", ms=4, label="PS")
            drawn.append((METHOD_LABEL["PS"], h))
            for label, h in drawn:
                if h is not None:
                    handles.setdefault(label, h)
            ax.set_xlim(0, 4 * np.pi)
            ax.set_title(f"{k + 1}: v = {sv[k]:.1f} m/s, $\\omega$ = {sw[k]:.1f} rad/s",
                         fontsize=8, loc="left")
            if k % 2 == 0:
                ax.set_ylabel(f"{coord} (rad)")
            if k >= 4:
                ax.set_xlabel("frequency (rad/s)")
        _legend_row(ax_leg, handles)
    _missing_note(fig, present, what=("one-speed series not in this build's time files"
                                      if series else "time solutions not computed in this "
                                      "build"))
    return fig


def figs_series_fft(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str,
                   coord: str) -> Figure:
    """Spectra at one speed and six cadences (weave peak fixed): ``fig_3_28`` (Fig 3.28, HS)
    and ``fig_3_29`` (Fig 3.29, CR)."""
    return figs_fft(ps, eig, time, model, coord, series=True)


# --------------------------------------------------------------------------------------------
# conservation of angular momentum (Fig 3.30, 3.31, F.1-F.3)
# --------------------------------------------------------------------------------------------

def fig_3_30(cam: Arrays, model: str) -> Figure:
    """Fig 3.30: CAM roll/steer angle and rate for the leg model and its simplifications.

    ``cam``: :func:`pedalrepro.figdata.cam_cases` (``labels``, ``t_s``, ``angle_rad`` and
    ``rate_rad_s`` of shape (n_case, 2, n_t)).
    """
    fig, axes = plt.subplots(2, 2, figsize=(WIDTH_IN, 5.6), sharex=True, layout="constrained")
    t = cam["t_s"]
    for c, label in enumerate(cam["labels"]):
        for j in range(2):
            axes[0, j].plot(t, cam["angle_rad"][c, j], label=str(label))
            axes[1, j].plot(t, cam["rate_rad_s"][c, j], label=str(label))
    for j, name in enumerate(("roll", "steer")):
        axes[0, j].set_title(f"{name} (model {model}, CAM)")
        axes[0, j].set_ylabel("angle (rad)")
        axes[1, j].set_ylabel("rate (rad/s)")
        axes[1, j].set_xlabel("t (s)")
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center", ncols=2,
               fontsize=8)
    return fig


def figs_neglected_momenta(data: Arrays, model: str) -> Figure:
    """Neglected momenta of Eq 3.29 as ratios of the leg momentum, one model each: ``fig_3_31``
    (Fig 3.31, HS), ``fig_f_1`` (CF), ``fig_f_2`` (HR), ``fig_f_3`` (CR).

    ``data``: :func:`pedalrepro.figdata.neglected_momenta` (``ratios`` (n_v, n_w, 3, 2)).
    Contours of each term at 1/4 and 1; filled where all three < 1/4; the GR band hatched.
    """
    from ..momentum_terms import NEGLECTED_TERMS

    speed_m_s, omega_rad_s, ratios = data["speed_m_s"], data["omega_rad_s"], data["ratios"]
    gear_ratios, wheel_radius_m = data["gear_band"], float(data["wheel_radius_m"])
    fig, axes = plt.subplots(1, 2, figsize=(WIDTH_IN, 4.2), sharey=True, layout="constrained")
    for j, (ax, name) in enumerate(zip(axes, ("roll", "steer"), strict=True)):
        r = ratios[..., j]
        ok = np.all(r < 0.25, axis=-1)
        ax.contourf(speed_m_s, omega_rad_s, ok.T.astype(float), levels=[0.5, 1.5],
                    colors=["#9ecae1"])
        for k, term in enumerate(NEGLECTED_TERMS):
            ax.contour(speed_m_s, omega_rad_s, r[..., k].T, levels=[0.25, 1.0],
                       colors=[f"C{k}"], linestyles=["-", "--"], linewidths=1)
            ax.plot([], [], color=f"C{k}", label=f"{term} = 1/4 (solid), 1 (dashed)")
        w_line = np.linspace(1e-3, omega_rad_s.max(), 100)
        v1 = gears.speed_m_s(gear_ratios[0], w_line, wheel_radius_m)
        v4 = gears.speed_m_s(gear_ratios[1], w_line, wheel_radius_m)
        ax.fill_betweenx(w_line, v1, np.minimum(v4, speed_m_s.max()), facecolor="none",
                         hatch="//", edgecolor="0.6", lw=0.0,
                         label=f"GR {gear_ratios[0]:g}-{gear_ratios[1]:g}")
        ax.plot(v1, w_line, color="0.5", lw=0.8)
        ax.plot(v4, w_line, color="0.5", lw=0.8)
        ax.set_xlim(0, speed_m_s.max())
        ax.set_title(f"{name}: model {model}")
        ax.set_xlabel("forward speed v (m/s)")
    axes[0].set_ylabel("cadence $\\omega$ (rad/s)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels + [], loc="outside lower center", ncols=2, fontsize=8,
               title="filled: all terms < 1/4 of $L_L$", title_fontsize=8)
    return fig


# --------------------------------------------------------------------------------------------
# normal cycling (Fig 3.35-3.38, G.7, G.8)
# --------------------------------------------------------------------------------------------

def _model_rows(n: int, height_per_row: float = 2.1):
    """A (models x roll/steer) grid at the book width."""
    fig, axes = plt.subplots(n, 2, figsize=(WIDTH_IN, 0.7 + height_per_row * n), sharex=True,
                             sharey=True, squeeze=False, layout="constrained")
    return fig, axes


def fig_3_35(ps: Mapping[str, Arrays], models: Sequence[str], grid: Arrays) -> Figure:
    """Fig 3.35: PS roll (left) and steer (right) amplitude maps of each model (rows), GR 1 and
    4 (dashed, each model's wheel), the normal-cycling ellipse (solid); ``grid``:
    :func:`pedalrepro.figdata.gear_grid`."""
    wheel_radius = {m: float(grid[f"wheel_radius_{m}_m"]) for m in models}
    fig, axes = _model_rows(len(models))
    ev, ew = grid["ellipse_speed_m_s"], grid["ellipse_omega_rad_s"]
    band = (float(np.min(grid["gear_ratios"])), float(np.max(grid["gear_ratios"])))
    cs = None
    for row, m in enumerate(models):
        for col, coord in enumerate(("roll", "steer")):
            ax = axes[row, col]
            cs = _ps_contour(ax, ps[m], coord, None, cam=False, colorbar=False)
            w_line = np.linspace(0, ps[m]["omega_rad_s"].max(), 50)
            for gr in band:
                ax.plot(gears.speed_m_s(gr, w_line, wheel_radius[m]), w_line, "w--", lw=0.9)
            ax.plot(ev, ew, "w-", lw=1.3)
            ax.set_xlim(0, ps[m]["speed_m_s"].max())
            ax.set_title(f"{m} {coord}")
            ax.set_xlabel("v (m/s)" if row == len(models) - 1 else "")
            ax.set_ylabel("$\\omega$ (rad/s)" if col == 0 else "")
    fig.colorbar(cs, ax=axes, label="amplitude at the cadence (rad)", shrink=0.6)
    return fig


def figs_gear_sections(sections: Arrays, models: Sequence[str]) -> Figure:
    """Roll (solid) and steer (dashed) amplitude along GR 1, 2, 3, 4: ``fig_3_36`` (Fig 3.36,
    HS, CF, HR, CR) and ``fig_g_8`` (Fig G.8, the benchmark).

    Model colours of :mod:`pedalrepro.figures.palette`; ``sections``:
    :func:`pedalrepro.figdata.gear_sections`."""
    grs = [float(g) for g in sections["gear_ratios"]]
    fig, axes = plt.subplots(2, 2, figsize=(WIDTH_IN, 5.4), sharey=True, sharex=True,
                             layout="constrained")
    for ax, gr in zip(axes.flat, grs, strict=False):
        for m in models:
            v = sections[f"{m}_{gr:g}_speed_m_s"]
            ax.plot(v, sections[f"{m}_{gr:g}_roll_rad"], color=model_colour(m), label=f"{m} roll")
            ax.plot(v, sections[f"{m}_{gr:g}_steer_rad"], color=model_colour(m), ls="--",
                    label=f"{m} steer")
        ax.set_title(f"GR {gr:g}")
        ax.set_ylim(0, 0.06)
    for ax in axes[-1]:
        ax.set_xlabel("forward speed v (m/s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("amplitude (rad)")
    fig.legend(*axes.flat[0].get_legend_handles_labels(), loc="outside lower center",
               ncols=4, fontsize=8)
    return fig


def fig_g_7(ps: Arrays, eig: Arrays) -> Figure:
    """Fig G.7: benchmark PS roll and steer maps (rows), CAM isoline with a 25 % band, the grid
    maximum; speed in m/s and km/h, cadence in rad/s and rpm, as the thesis."""
    fig, axes = plt.subplots(2, 1, figsize=(WIDTH_IN, 7.4), layout="constrained")
    for ax, coord in zip(axes, ("roll", "steer"), strict=True):
        _ps_contour(ax, ps, coord, eig, cam_band=0.25)
        amp = ps[f"{coord}_amp_rad"]
        i, j = np.unravel_index(np.argmax(amp), amp.shape)
        ax.plot(ps["speed_m_s"][i], ps["omega_rad_s"][j], "r+", ms=12, mew=2)
        ax.set_title(f"benchmark {coord}: grid maximum at {ps['speed_m_s'][i]:.2f} m/s, "
                     f"{ps['omega_rad_s'][j]:.2f} rad/s", fontsize=9)
        sec = ax.secondary_xaxis("top", functions=(lambda x: 3.6 * x, lambda x: x / 3.6))
        sec.set_xlabel("speed (km/h)")
        _rpm_axis(ax)
    return fig


def rd_norm() -> BoundaryNorm:
    """Colour norm of the logarithmic RD maps: one colour between two labelled levels."""
    return BoundaryNorm(RD_LOG_LEVELS_PERCENT, plt.get_cmap("magma").N, extend="neither")


def rd_colorbar(fig: Figure, mappable, axes, label: str = "RD (%)"):
    """Colour bar of the RD maps with the thesis's levels labelled (0.1, 1, 2.5, 5, 10, 25,
    100 %)."""
    cb = fig.colorbar(mappable, ax=axes, label=label, shrink=0.7, ticks=list(RD_TICKS_PERCENT))
    cb.ax.set_yticklabels([f"{x:g}" for x in RD_TICKS_PERCENT])
    return cb


def rd_map(ax, v, w, rd, eig=None, title="", log: bool = True):
    """One RD map (Eq 3.26, percent) over speed (x) and cadence (y): logarithmic with the
    thesis's levels (:func:`rd_norm`), or linear for the parameter comparisons; the weave line
    and self-stable lines of ``eig`` when given. Returns the contour set (for the colour bar)."""
    if log:
        # NaN (no forcing: zero reference amplitude) stays blank, inf at the top level
        shown = np.clip(np.asarray(rd, float), RD_LOG_LEVELS_PERCENT[0],
                        RD_LOG_LEVELS_PERCENT[-1])
        cs = ax.contourf(v, w, shown.T, levels=RD_LOG_LEVELS_PERCENT, norm=rd_norm(),
                         cmap="magma")
    else:
        cs = ax.contourf(v, w, rd.T, levels=RD_LEVELS_PERCENT, cmap="magma_r", extend="max")
    _decorate(ax, eig, w.max())
    ax.set_title(title, fontsize=8)
    return cs


def _label_rd_grid(fig: Figure, axes, cs, log: bool = True) -> None:
    """Axis labels of a grid of RD maps (v below, omega on the left) and one RD colour bar
    (none when no panel was drawn, ``cs is None``)."""
    for ax in axes[-1]:
        ax.set_xlabel("v (m/s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("$\\omega$ (rad/s)")
    if cs is not None:
        if log:
            rd_colorbar(fig, cs, axes)
        else:
            fig.colorbar(cs, ax=axes, label="RD (%)", shrink=0.7)


def fig_3_37(rd: Mapping[str, Arrays], eigen: Mapping[str, Arrays],
                     models: Sequence[str]) -> Figure:
    """Fig 3.37: RD of each grid point from the reference 60 rpm, 5 m/s (evaluation point 4)."""
    fig, axes = _model_rows(len(models))
    cs = None
    for row, m in enumerate(models):
        for col, coord in enumerate(("roll", "steer")):
            d = rd[m]
            cs = rd_map(axes[row, col], d["speed_m_s"], d["omega_rad_s"], d[f"4_{coord}"],
                         eigen.get(m), f"{m} {coord}: RD vs 60 rpm, 5 m/s", log=False)
    _label_rd_grid(fig, axes, cs, log=False)
    return fig


def fig_3_38(pairs: Arrays) -> Figure:
    """Fig 3.38: RD between models: HR vs HS, CR vs CF (posture), CR vs HR (bicycle); rows =
    pairs, columns roll and steer."""
    keys = [("5", "HR", "HS"), ("5", "CR", "CF"), ("6", "CR", "HR")]
    fig, axes = _model_rows(len(keys))
    v, w = pairs["speed_m_s"], pairs["omega_rad_s"]
    cs = None
    for row, (p, a, b) in enumerate(keys):
        for col, coord in enumerate(("roll", "steer")):
            key = f"{p}_{a}_vs_{b}_{coord}"
            if key in pairs:
                cs = rd_map(axes[row, col], v, w, pairs[key], None,
                             f"point {p}: {a} vs {b}, {coord}", log=False)
    _label_rd_grid(fig, axes, cs, log=False)
    return fig


def figs_rd_points(rd: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str,
                  coord: str) -> Figure:
    """RD maps of evaluation points 1a, 1b, 1c, 2b, 3a, 3b (3 rows of two), one model and
    coordinate each: Figs 3.32, 3.33, H.1-H.6, ``fig_3_32``, ``fig_3_33``, ``fig_h_1``,
    ``fig_h_2``, ``fig_h_3``, ``fig_h_4``, ``fig_h_5``, ``fig_h_6``.

    1a (NT vs NP) and 1b (LA vs NT) need the non-linear time solutions; they are drawn when
    present, otherwise the panel says so.
    """
    from ..relative_difference import relative_difference

    fig, axes = plt.subplots(3, 2, figsize=(WIDTH_IN, 7.6), sharex=True, sharey=True,
                             layout="constrained")
    tv, tw = rd["time_speed_m_s"], rd["time_omega_rad_s"]
    panels = []
    if "NP" in time and "NT" in time:
        panels.append(("1a: NP to NT", tv, tw, relative_difference(
            time["NP"][f"{coord}_amp_rad"], time["NT"][f"{coord}_amp_rad"])))
    else:
        panels.append(("1a: needs NT and NP", None, None, None))
    if "NT" in time and "LA" in time:
        panels.append(("1b: NT to LA", tv, tw, relative_difference(
            time["NT"][f"{coord}_amp_rad"], time["LA"][f"{coord}_amp_rad"])))
    else:
        panels.append(("1b: needs NT", None, None, None))
    panels += [("1c: PS to CAM", rd["speed_m_s"], rd["omega_rad_s"], rd[f"1c_{coord}"]),
               ("2b: T(w,3w,5w) to T(w), LA", tv, tw, rd[f"2b_{coord}"]),
               ("3a: LA to LN", tv, tw, rd[f"3a_{coord}"]),
               ("3b: PS to LA Hann-DFT", tv, tw, rd[f"3b_{coord}"])]
    cs = None
    for ax, (title, v, w, r) in zip(axes.flat, panels, strict=True):
        if r is None:
            ax.text(0.5, 0.5, "not available here", ha="center", va="center",
                    transform=ax.transAxes)
            ax.set_title(title, fontsize=8)
            continue
        cs = rd_map(ax, v, w, r, eig, title)
    fig.suptitle(f"model {model}, {coord}: relative differences (Eq 3.26)", fontsize=9)
    _label_rd_grid(fig, axes, cs)
    _missing_note(fig, [m for m in ALL_TIME_METHODS if m in time])
    return fig
