"""Figures of the linear open-loop response (thesis Sec 3, Appendices F, G, H).

Every function takes loaded result arrays (dicts of numpy arrays, as ``dict(np.load(npz))``) and
returns a matplotlib ``Figure``; :data:`FIGURE_SPECS` maps each figure id to its function and
arguments so that the Snakemake rule and the notebooks draw the same thing.

Axes follow the thesis: forward speed (m/s) horizontally, cadence (rad/s) vertically.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from .. import gears, linear, spectral

Arrays = Mapping[str, np.ndarray]

#: Every time-solution method of the thesis (FIGURES.md); the linear part makes LA and LN.
ALL_TIME_METHODS: tuple[str, ...] = ("LA", "LN", "NT", "NP")
METHOD_STYLE = {"LA": dict(color="C0", lw=1.2), "LN": dict(color="C1", lw=0.9, ls="--"),
                "NT": dict(color="C2", lw=0.9, ls="-."), "NP": dict(color="C3", lw=0.9, ls=":")}
METHOD_LABEL = {"LA": "LA linear analytic", "LN": "LN linear numerical",
                "NT": "NT non-linear, torques", "NP": "NP non-linear, pedalling legs"}
MODELS4 = ("HS", "CF", "HR", "CR")
AMP_LEVELS = np.linspace(0.0, 0.04, 9)
RD_LEVELS = np.array([1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 1, 2.5, 5, 10, 25, 50, 100, 1e3, 1e6])
#: Linear RD levels (percent) for the parameter comparisons of evaluation points 4-6.
RD_LEVELS_PERCENT = np.array([0, 5, 10, 25, 50, 75, 100, 150, 200])

# --------------------------------------------------------------------------------------------
# figure id -> (function name, keyword arguments). Used by rules/linear.smk and the notebooks.
# --------------------------------------------------------------------------------------------
FIGURE_SPECS: dict[str, tuple[str, dict]] = {
    "fig_3_6": ("fig_eigenvalues", {"models": ("benchmark",)}),
    "fig_3_8": ("fig_gear_grid", {}),
    "fig_3_9": ("fig_eigenvalues", {"models": MODELS4}),
    "fig_3_30": ("fig_cam_time", {"model": "HS"}),
    "fig_3_31": ("fig_neglected_momenta", {"model": "HS"}),
    "fig_f_1": ("fig_neglected_momenta", {"model": "CF"}),
    "fig_f_2": ("fig_neglected_momenta", {"model": "HR"}),
    "fig_f_3": ("fig_neglected_momenta", {"model": "CR"}),
    "fig_3_35": ("fig_amplitude_maps", {"models": MODELS4}),
    "fig_3_36": ("fig_gear_sections", {"models": MODELS4}),
    "fig_g_7": ("fig_benchmark_ps", {"model": "benchmark"}),
    "fig_g_8": ("fig_gear_sections", {"models": ("benchmark",)}),
    "fig_3_37": ("fig_rd_reference", {"models": MODELS4}),
    "fig_3_38": ("fig_rd_models", {}),
}
for _i, (_m, _c) in enumerate([(m, c) for m in MODELS4 for c in ("roll", "steer")]):
    FIGURE_SPECS[f"fig_3_{10 + _i}"] = ("fig_ps_time", {"model": _m, "coord": _c})
    FIGURE_SPECS[f"fig_3_{20 + _i}"] = ("fig_fft", {"model": _m, "coord": _c})
for _fid, _m, _c in [("fig_g_1", "HS", "roll"), ("fig_g_2", "CF", "roll"),
                     ("fig_g_3", "CF", "steer"), ("fig_g_4", "HR", "roll"),
                     ("fig_g_5", "HR", "steer"), ("fig_g_6", "CR", "roll")]:
    FIGURE_SPECS[_fid] = ("fig_ps_time", {"model": _m, "coord": _c, "single_harmonic": True})
FIGURE_SPECS["fig_3_18"] = ("fig_series_time", {"model": "HS", "coord": "steer"})
FIGURE_SPECS["fig_3_19"] = ("fig_series_time", {"model": "CR", "coord": "steer"})
FIGURE_SPECS["fig_3_28"] = ("fig_series_fft", {"model": "HS", "coord": "steer"})
FIGURE_SPECS["fig_3_29"] = ("fig_series_fft", {"model": "CR", "coord": "steer"})
# Fig H.6's caption repeats "roll, HR" (Fig 3.32); the set of appendix figures implies HR steer.
for _fid, _m, _c in [("fig_3_32", "HR", "roll"), ("fig_3_33", "CF", "roll"),
                     ("fig_h_1", "HS", "roll"), ("fig_h_2", "HS", "steer"),
                     ("fig_h_3", "CF", "steer"), ("fig_h_4", "CR", "roll"),
                     ("fig_h_5", "CR", "steer"), ("fig_h_6", "HR", "steer")]:
    FIGURE_SPECS[_fid] = ("fig_rd_points", {"model": _m, "coord": _c})

#: What each figure kind reads: "eigen", "ps", "time", "rd", "pairs" (per model or global).
NEEDS: dict[str, tuple[str, ...]] = {
    "fig_eigenvalues": ("eigen",), "fig_gear_grid": (), "fig_cam_time": (),
    "fig_neglected_momenta": (), "fig_amplitude_maps": ("ps",), "fig_gear_sections": (),
    "fig_benchmark_ps": ("ps", "eigen"), "fig_rd_reference": ("rd", "eigen"),
    "fig_rd_models": ("pairs",), "fig_ps_time": ("ps", "eigen", "time"),
    "fig_fft": ("ps", "eigen", "time"), "fig_series_time": ("ps", "eigen", "time"),
    "fig_series_fft": ("ps", "eigen", "time"), "fig_rd_points": ("rd", "eigen", "time"),
}


#: Figure groups drawn by one Snakemake job each (start-up cost paid once per group).
FIGURE_GROUPS: tuple[str, ...] = ("overview", "time", "rd")
_TIME_KINDS = ("fig_ps_time", "fig_fft", "fig_series_time", "fig_series_fft")


def figure_group(group: str) -> list[str]:
    """Figure ids of a group: ``"time"`` (reads the time solutions of every method),
    ``"rd"`` (evaluation points 1-3) or ``"overview"`` (everything else)."""
    if group not in FIGURE_GROUPS:
        raise ValueError(f"unknown figure group {group!r}: expected one of {FIGURE_GROUPS}")

    def kind(func: str) -> str:
        if func == "fig_rd_points":
            return "rd"
        return "time" if func in _TIME_KINDS else "overview"

    return sorted(fid for fid, (func, _) in FIGURE_SPECS.items() if kind(func) == group)


def spec_models(fid: str) -> tuple[str, ...]:
    """Models a figure draws."""
    kw = FIGURE_SPECS[fid][1]
    if "models" in kw:
        return tuple(kw["models"])
    if "model" in kw:
        return (kw["model"],)
    return ()


# --------------------------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------------------------

def _missing_note(fig: Figure, present: Sequence[str]) -> list[str]:
    missing = [m for m in ALL_TIME_METHODS if m not in present]
    if missing:
        fig.text(0.01, 0.003, "not available here: " + ", ".join(missing)
                 + " (time solutions not computed in this build)", fontsize=7, color="0.35",
                 ha="left", va="bottom")
    return missing


def _stable_ranges(eig: Arrays) -> np.ndarray:
    return np.asarray(eig["stable_ranges_m_s"]).reshape(-1, 2)


def _decorate(ax, eig: Arrays | None, y_max: float) -> None:
    """Weave imaginary part (dashed) and the self-stable range (shaded)."""
    if eig is None:
        return
    v, f = eig["speed_m_s"], eig["weave_frequency_rad_s"]
    f = np.where(f > 0, f, np.nan)
    ax.plot(v, f, "w--", lw=1.1)
    ax.plot(v, f, "k--", lw=0.6, label="Im(weave)")
    for lo, hi in _stable_ranges(eig):
        ax.axvspan(lo, hi, color="w", alpha=0.18, lw=0)
        ax.axvline(lo, color="w", lw=0.8)
        ax.axvline(hi, color="w", lw=0.8)
    ax.set_ylim(0, y_max)


def _ps_contour(ax, ps: Arrays, coord: str, eig: Arrays | None = None, *, cam: bool = True,
                levels=AMP_LEVELS, colorbar: bool = True, cam_band: float | None = None):
    v, w = ps["speed_m_s"], ps["omega_rad_s"]
    amp = ps[f"{coord}_amp_rad"]
    cs = ax.contourf(v, w, amp.T, levels=levels, extend="max", cmap="viridis")
    if cam:
        level = float(ps[f"cam_{coord}_rad"])
        if cam_band:
            ax.contourf(v, w, amp.T, levels=[level * (1 - cam_band), level * (1 + cam_band)],
                        colors=["#7b0c2e"], alpha=0.3)
        ax.contour(v, w, amp.T, levels=[level], colors=["#7b0c2e"], linewidths=1.8)
    _decorate(ax, eig, w.max())
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("cadence $\\omega$ (rad/s)")
    if colorbar:
        ax.figure.colorbar(cs, ax=ax, label=f"{coord} amplitude (rad)")
    return cs


def _label_points(ax, speeds, omegas, color="w") -> None:
    for i, (a, b) in enumerate(zip(speeds, omegas, strict=True)):
        ax.plot(a, b, "o", ms=9, mfc="none", mec=color)
        ax.text(a, b, str(i + 1), color=color, ha="center", va="center", fontsize=7)


def _ps_time(ps: Arrays, coord: str, speed: float, omega: float, t: np.ndarray) -> np.ndarray:
    """The periodic particular solution in time at (speed, omega) by nearest PS grid point."""
    i = int(np.argmin(np.abs(ps["speed_m_s"] - speed)))
    j = int(np.argmin(np.abs(ps["omega_rad_s"] - omega)))
    q = ps[coord][i, j]
    return np.real(np.exp(1j * np.multiply.outer(t, ps["n"] * omega)) @ q)


# --------------------------------------------------------------------------------------------
# eigenvalues, gears
# --------------------------------------------------------------------------------------------

def eigen_panel(ax, e: Arrays, title: str) -> None:
    """One eigenvalue-vs-speed panel (``linear_eigen`` npz format): Re by mode, Im weave.

    Real parts solid, coloured by mode; the weave imaginary part dashed; self-stable range shaded.
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
        ax.axvspan(lo, hi, color="0.85", zorder=0, label="self-stable")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_ylim(-10, 10)
    ax.set_title(title)
    ax.set_xlabel("v (m/s)")
    ax.set_ylabel("eigenvalue (1/s)")


def fig_eigenvalues(eigen: Mapping[str, Arrays], models: Sequence[str]) -> Figure:
    """Fig 3.6 (benchmark) / Fig 3.9 (HS, CF, HR, CR): eigenvalues vs speed, one panel each."""
    n = len(models)
    fig, axes = plt.subplots(1 if n == 1 else 2, 1 if n == 1 else 2, squeeze=False,
                             figsize=(6.5, 4.2) if n == 1 else (8, 6), sharex=True)
    for ax, m in zip(axes.flat, models, strict=False):
        eigen_panel(ax, eigen[m], m)
    axes.flat[0].legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    return fig


def fig_gear_grid(speed_m_s: np.ndarray, omega_rad_s: np.ndarray, gear_ratios: Sequence[float],
                  wheel_radius_m: float, normal_speed_kmh, normal_cadence_rpm,
                  reference: tuple[float, float] | None = None) -> Figure:
    """Fig 3.8: the speed-cadence grid with gear-ratio lines and the 'normal cycling' ellipse."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    vv, ww = np.meshgrid(speed_m_s, omega_rad_s)
    ax.plot(vv.ravel(), ww.ravel(), ".", color="0.75", ms=1.5)
    w_line = np.linspace(0, omega_rad_s.max(), 50)
    for gr in gear_ratios:
        v_line = gears.speed_m_s(gr, w_line, wheel_radius_m)
        keep = v_line <= speed_m_s.max()
        ax.plot(v_line[keep], w_line[keep], label=f"GR {gr:g}")
    ev, ew = gears.normal_cycling_ellipse(normal_speed_kmh, normal_cadence_rpm)
    ax.plot(ev, ew, "k-", lw=1.5, label="normal cycling")
    if reference:
        ax.plot(*reference, "k*", ms=9, label="reference 60 rpm, 5 m/s")
    ax.set_xlim(0, speed_m_s.max())
    ax.set_ylim(0, omega_rad_s.max())
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("cadence $\\omega$ (rad/s)")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(f"wheel radius {wheel_radius_m:.3f} m")
    return fig


# --------------------------------------------------------------------------------------------
# particular solution + time solutions (Fig 3.10-3.19, G.1-G.6)
# --------------------------------------------------------------------------------------------

def _time_grid_fig(title: str):
    fig = plt.figure(figsize=(11, 5.2))
    gs = fig.add_gridspec(3, 4, width_ratios=[2.2, 0.08, 1, 1], wspace=0.35, hspace=0.55)
    ax_map = fig.add_subplot(gs[:, 0])
    axes = [fig.add_subplot(gs[i, 2 + j]) for i in range(3) for j in range(2)]
    fig.suptitle(title, fontsize=9)
    return fig, ax_map, axes


def fig_ps_time(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str, coord: str,
                single_harmonic: bool = False) -> Figure:
    """Fig 3.10-3.17 (and G.1-G.6): PS amplitude map (left) and time solutions at six points.

    Left: particular-solution amplitude at the cadence, the CAM isoline (burgundy), the weave
    imaginary part (dashed) and the self-stable range (light band), with the six numbered
    points. Right: the time solutions of every method present; dotted grey = the particular
    solution. ``single_harmonic`` adds LA driven by the cadence harmonic only (Appendix G).
    """
    fig, ax_map, axes = _time_grid_fig(f"model {model}: {coord} (particular solution and time "
                                       "solutions)")
    _ps_contour(ax_map, ps, coord, eig)
    present = [m for m in ALL_TIME_METHODS if m in time]
    ref = time[present[0]] if present else None
    if ref is not None:
        _label_points(ax_map, ref["example_speed_m_s"], ref["example_omega_rad_s"])
        for k, ax in enumerate(axes):
            v, w = ref["example_speed_m_s"][k], ref["example_omega_rad_s"][k]
            for m in present:
                d = time[m]
                ax.plot(d["example_t_s"], d[f"example_{coord}_rad"][k], label=m,
                        **METHOD_STYLE[m])
            if single_harmonic and "LA" in time and f"example_{coord}_h1_rad" in time["LA"]:
                d = time["LA"]
                ax.plot(d["example_t_s"], d[f"example_{coord}_h1_rad"][k], color="C4", lw=0.7,
                        label="LA, T($\\omega$) only")
            t = ref["example_t_s"]
            ax.plot(t, _ps_time(ps, coord, v, w, t), color="0.5", lw=0.6, ls=":", label="PS")
            lim = 3 * max(float(np.abs(_ps_time(ps, coord, v, w, t[: len(t) // 4 + 2])).max()),
                          1e-4)
            ax.set_ylim(-lim, lim)
            ax.set_title(f"{k + 1}: v={v:.1f} m/s, $\\omega$={w:.1f} rad/s", fontsize=7)
            ax.tick_params(labelsize=6)
        axes[-1].set_xlabel("t (s)")
        axes[0].legend(fontsize=6, loc="upper right")
    _missing_note(fig, present)
    return fig


def fig_series_time(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str,
                    coord: str) -> Figure:
    """Fig 3.18 / 3.19: time solutions at one speed and six cadences (weave visible)."""
    fig, ax_map, axes = _time_grid_fig(f"model {model}: {coord}, one speed, six cadences")
    _ps_contour(ax_map, ps, coord, eig)
    present = [m for m in ALL_TIME_METHODS if m in time and "series_speed_m_s" in time[m]]
    if present:
        ref = time[present[0]]
        _label_points(ax_map, ref["series_speed_m_s"], ref["series_omega_rad_s"])
        t = ref["example_t_s"]
        for k, ax in enumerate(axes):
            v, w = ref["series_speed_m_s"][k], ref["series_omega_rad_s"][k]
            for m in present:
                ax.plot(t, time[m][f"series_{coord}_rad"][k], label=m, **METHOD_STYLE[m])
            ax.plot(t, _ps_time(ps, coord, v, w, t), color="0.5", lw=0.6, ls=":", label="PS")
            ax.set_title(f"{k + 1}: v={v:.1f} m/s, $\\omega$={w:.1f} rad/s", fontsize=7)
            ax.tick_params(labelsize=6)
        axes[0].legend(fontsize=6)
    _missing_note(fig, present)
    return fig


# --------------------------------------------------------------------------------------------
# frequency domain (Fig 3.20-3.29)
# --------------------------------------------------------------------------------------------

def _spectrum_panel(ax, d: Arrays, key: str, k: int, fs: float, style: dict, label: str,
                    windowed: bool = True) -> None:
    if key not in d:  # e.g. a method file without the one-speed series of Fig 3.28/3.29
        return
    x = d[key][k]
    x = x[np.isfinite(x)]
    if len(x) < 8:
        return
    f, a = spectral.spectrum(x, fs, "hann" if windowed else None)
    ax.semilogy(2 * np.pi * f, np.maximum(a, 1e-12), label=label, **style)


def fig_fft(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str, coord: str,
            series: bool = False) -> Figure:
    """Fig 3.20-3.27: Hann-DFT cadence amplitude vs PS (left), spectra at six points (right).

    Left: the Hann-windowed DFT amplitude of the LA time solutions on the time grid (colours,
    same scale as the PS) with the PS amplitude as black contour lines. Right: spectra of the
    example runs with the Hann window (solid) and without (thin grey, LA), the PS amplitude as a
    black dot at the cadence.
    """
    prefix = "series" if series else "example"
    fig, ax_map, axes = _time_grid_fig(f"model {model}: {coord}, frequency domain")
    present = [m for m in ALL_TIME_METHODS if m in time]
    v, w = ps["speed_m_s"], ps["omega_rad_s"]
    if present:
        d0 = time[present[0]]
        cs = ax_map.pcolormesh(d0["speed_m_s"], d0["omega_rad_s"],
                               d0[f"{coord}_amp_rad"].T, vmin=0, vmax=AMP_LEVELS[-1],
                               shading="nearest", cmap="viridis")
        fig.colorbar(cs, ax=ax_map, label=f"{present[0]} Hann-DFT {coord} amplitude (rad)")
    ax_map.contour(v, w, ps[f"{coord}_amp_rad"].T, levels=AMP_LEVELS[1:], colors="k",
                   linewidths=0.5)
    _decorate(ax_map, eig, w.max())
    ax_map.set_xlabel("forward speed v (m/s)")
    ax_map.set_ylabel("cadence $\\omega$ (rad/s)")
    if present:
        ref = time[present[0]]
        sv, sw = ref[f"{prefix}_speed_m_s"], ref[f"{prefix}_omega_rad_s"]
        _label_points(ax_map, sv, sw)
        for k, ax in enumerate(axes):
            fs = float(ref["sample_rate_hz"]) if "sample_rate_hz" in ref else 1.0 / float(
                np.diff(ref["example_t_s"][:2])[0])
            for m in present:
                _spectrum_panel(ax, time[m], f"{prefix}_{coord}_rad", k, fs, METHOD_STYLE[m], m)
            if "LA" in time:
                _spectrum_panel(ax, time["LA"], f"{prefix}_{coord}_rad", k, fs,
                                dict(color="0.6", lw=0.5), "LA, no window", windowed=False)
            i = int(np.argmin(np.abs(v - sv[k])))
            j = int(np.argmin(np.abs(w - sw[k])))
            ax.plot(sw[k], ps[f"{coord}_amp_rad"][i, j], "ko", ms=3, label="PS")
            ax.set_xlim(0, 4 * np.pi)
            ax.set_title(f"{k + 1}: v={sv[k]:.1f} m/s, $\\omega$={sw[k]:.1f} rad/s", fontsize=7)
            ax.tick_params(labelsize=6)
        axes[-1].set_xlabel("frequency (rad/s)")
        axes[0].legend(fontsize=5)
    _missing_note(fig, present)
    return fig


def fig_series_fft(ps: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str,
                   coord: str) -> Figure:
    """Fig 3.28 / 3.29: spectra at one speed and six cadences (weave peak fixed)."""
    return fig_fft(ps, eig, time, model, coord, series=True)


# --------------------------------------------------------------------------------------------
# conservation of angular momentum (Fig 3.30, 3.31, F.1-F.3)
# --------------------------------------------------------------------------------------------

def fig_cam_time(cases: Mapping[str, Mapping[str, np.ndarray]], model: str) -> Figure:
    """Fig 3.30: CAM roll/steer angle and rate for the leg model and its simplifications.

    ``cases``: label -> dict with ``t_s``, ``angle_rad`` (2, n_t), ``rate_rad_s`` (2, n_t).
    """
    fig, axes = plt.subplots(2, 2, figsize=(8, 5), sharex=True)
    for label, c in cases.items():
        for j in range(2):
            axes[0, j].plot(c["t_s"], c["angle_rad"][j], label=label)
            axes[1, j].plot(c["t_s"], c["rate_rad_s"][j], label=label)
    for j, name in enumerate(("roll", "steer")):
        axes[0, j].set_title(f"{name} (model {model}, CAM)")
        axes[0, j].set_ylabel("angle (rad)")
        axes[1, j].set_ylabel("rate (rad/s)")
        axes[1, j].set_xlabel("t (s)")
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def fig_neglected_momenta(speed_m_s: np.ndarray, omega_rad_s: np.ndarray, ratios: np.ndarray,
                          model: str, wheel_radius_m: float, gear_ratios=(1, 4)) -> Figure:
    """Fig 3.31, F.1-F.3: neglected momenta of Eq 3.29 as ratios of the leg momentum.

    ``ratios`` (n_v, n_w, 3, 2). Contours of each term at 1/4; filled where all three < 1/4;
    the GR 1-4 band hatched.
    """
    from ..momentum import NEGLECTED_TERMS

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), sharey=True)
    for j, (ax, name) in enumerate(zip(axes, ("roll", "steer"), strict=True)):
        r = ratios[..., j]
        ok = np.all(r < 0.25, axis=-1)
        ax.contourf(speed_m_s, omega_rad_s, ok.T.astype(float), levels=[0.5, 1.5],
                    colors=["#9ecae1"])
        for k, term in enumerate(NEGLECTED_TERMS):
            cs = ax.contour(speed_m_s, omega_rad_s, r[..., k].T, levels=[0.25, 1.0],
                            colors=[f"C{k}"], linestyles=["-", "--"], linewidths=1)
            ax.plot([], [], color=f"C{k}", label=f"{term} = 1/4 (solid), 1 (dashed)")
            del cs
        w_line = np.linspace(1e-3, omega_rad_s.max(), 100)
        v1 = gears.speed_m_s(gear_ratios[0], w_line, wheel_radius_m)
        v4 = gears.speed_m_s(gear_ratios[1], w_line, wheel_radius_m)
        ax.fill_betweenx(w_line, v1, np.minimum(v4, speed_m_s.max()), facecolor="none",
                         hatch="//", edgecolor="0.6", lw=0.0,
                         label=f"GR {gear_ratios[0]}-{gear_ratios[1]}")
        ax.plot(v1, w_line, color="0.5", lw=0.8)
        ax.plot(v4, w_line, color="0.5", lw=0.8)
        ax.set_xlim(0, speed_m_s.max())
        ax.set_title(f"{name}: model {model}; filled = all terms < 1/4 of $L_L$")
        ax.set_xlabel("forward speed v (m/s)")
    axes[0].set_ylabel("cadence $\\omega$ (rad/s)")
    axes[0].legend(fontsize=6, loc="lower right")
    fig.tight_layout()
    return fig


# --------------------------------------------------------------------------------------------
# normal cycling (Fig 3.35-3.38, G.7, G.8)
# --------------------------------------------------------------------------------------------

def fig_amplitude_maps(ps: Mapping[str, Arrays], models: Sequence[str], wheel_radius: Mapping,
                       normal_speed_kmh, normal_cadence_rpm, gear_ratios=(1, 4)) -> Figure:
    """Fig 3.35: PS roll and steer amplitude maps of all models, GR 1 and 4, ellipse."""
    fig, axes = plt.subplots(2, len(models), figsize=(3 * len(models), 5.6), sharex=True,
                             sharey=True, squeeze=False)
    ev, ew = gears.normal_cycling_ellipse(normal_speed_kmh, normal_cadence_rpm)
    for col, m in enumerate(models):
        for row, coord in enumerate(("roll", "steer")):
            ax = axes[row, col]
            cs = _ps_contour(ax, ps[m], coord, None, cam=False, colorbar=False)
            w_line = np.linspace(0, ps[m]["omega_rad_s"].max(), 50)
            for gr in gear_ratios:
                ax.plot(gears.speed_m_s(gr, w_line, wheel_radius[m]), w_line, "w--", lw=0.8)
            ax.plot(ev, ew, "w-", lw=1.2)
            ax.set_xlim(0, ps[m]["speed_m_s"].max())
            ax.set_title(f"{m} {coord}")
            if row == 0:
                ax.set_xlabel("")
            if col:
                ax.set_ylabel("")
    fig.colorbar(cs, ax=axes, label="amplitude (rad)", shrink=0.8)
    return fig


def gear_section(model_name: str, torque, gear_ratio: float, wheel_radius: float,
                 speed_m_s: np.ndarray, omega_max_rad_s: float):
    """PS cadence amplitudes along one gear ratio (Fig 3.36): speeds, roll, steer."""
    from ..response import particular_solution

    w = gears.cadence_rad_s(gear_ratio, speed_m_s, wheel_radius)
    keep = w <= omega_max_rad_s
    r, s = particular_solution(linear.linear_model(model_name), speed_m_s[keep], w[keep], torque)
    k = int(np.nonzero(np.asarray(torque.n) == 1)[0][0])
    return speed_m_s[keep], np.abs(r[:, k]), np.abs(s[:, k])


def fig_gear_sections(sections: Mapping[str, Mapping[float, tuple]], models: Sequence[str])\
        -> Figure:
    """Fig 3.36 / G.8: roll (solid) and steer (dashed) amplitude along GR 1, 2, 3, 4."""
    grs = sorted(next(iter(sections.values())).keys())
    fig, axes = plt.subplots(1, len(grs), figsize=(3 * len(grs), 3.4), sharey=True)
    axes = np.atleast_1d(axes)
    for ax, gr in zip(axes, grs, strict=True):
        for c, m in enumerate(models):
            v, r, s = sections[m][gr]
            ax.plot(v, r, color=f"C{c}", label=f"{m} roll")
            ax.plot(v, s, color=f"C{c}", ls="--", label=f"{m} steer")
        ax.set_title(f"GR {gr:g}")
        ax.set_xlabel("forward speed v (m/s)")
        ax.set_ylim(0, 0.06)
    axes[0].set_ylabel("amplitude at the cadence (rad)")
    axes[0].legend(fontsize=6)
    fig.tight_layout()
    return fig


def fig_benchmark_ps(ps: Arrays, eig: Arrays) -> Figure:
    """Fig G.7: benchmark PS roll and steer maps, CAM isoline with a 25 % band, the maximum."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, coord in zip(axes, ("roll", "steer"), strict=True):
        _ps_contour(ax, ps, coord, eig, cam_band=0.25)
        amp = ps[f"{coord}_amp_rad"]
        i, j = np.unravel_index(np.argmax(amp), amp.shape)
        ax.plot(ps["speed_m_s"][i], ps["omega_rad_s"][j], "r+", ms=10)
        ax.set_title(f"benchmark {coord}: grid maximum at {ps['speed_m_s'][i]:.2f} m/s, "
                     f"{ps['omega_rad_s'][j]:.2f} rad/s", fontsize=8)
        sec = ax.secondary_xaxis("top", functions=(lambda x: 3.6 * x, lambda x: x / 3.6))
        sec.set_xlabel("km/h")
    fig.tight_layout()
    return fig


def _rd_map(ax, v, w, rd, eig=None, title="", log: bool = True):
    if log:
        cs = ax.contourf(v, w, np.clip(rd, 1e-10, 1e6).T, levels=RD_LEVELS,
                         norm=plt.matplotlib.colors.LogNorm(1e-10, 1e6), cmap="magma",
                         extend="both")
    else:
        cs = ax.contourf(v, w, rd.T, levels=RD_LEVELS_PERCENT, cmap="magma_r", extend="max")
    _decorate(ax, eig, w.max())
    ax.set_title(title, fontsize=8)
    return cs


def _label_rd_grid(fig: Figure, axes, cs) -> None:
    """Axis labels of a grid of RD maps (v below, omega on the left) and one RD colour bar
    (none when no panel was drawn, ``cs is None``)."""
    for ax in axes[-1]:
        ax.set_xlabel("v (m/s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("$\\omega$ (rad/s)")
    if cs is not None:
        fig.colorbar(cs, ax=axes, label="RD (%)", shrink=0.8)


def fig_rd_reference(rd: Mapping[str, Arrays], eigen: Mapping[str, Arrays],
                     models: Sequence[str]) -> Figure:
    """Fig 3.37: RD of each grid point from the reference 60 rpm, 5 m/s (evaluation point 4)."""
    fig, axes = plt.subplots(2, len(models), figsize=(3 * len(models), 5.6), sharex=True,
                             sharey=True, squeeze=False)
    cs = None
    for col, m in enumerate(models):
        for row, coord in enumerate(("roll", "steer")):
            d = rd[m]
            cs = _rd_map(axes[row, col], d["speed_m_s"], d["omega_rad_s"], d[f"4_{coord}"],
                         eigen.get(m), f"{m} {coord}: RD vs 60 rpm, 5 m/s", log=False)
    _label_rd_grid(fig, axes, cs)
    return fig


def fig_rd_models(pairs: Arrays) -> Figure:
    """Fig 3.38: RD between models: HR vs HS, CR vs CF (posture), CR vs HR (bicycle)."""
    keys = [("5", "HR", "HS"), ("5", "CR", "CF"), ("6", "CR", "HR")]
    fig, axes = plt.subplots(2, 3, figsize=(10, 5.6), sharex=True, sharey=True)
    v, w = pairs["speed_m_s"], pairs["omega_rad_s"]
    cs = None
    for col, (p, a, b) in enumerate(keys):
        for row, coord in enumerate(("roll", "steer")):
            key = f"{p}_{a}_vs_{b}_{coord}"
            if key in pairs:
                cs = _rd_map(axes[row, col], v, w, pairs[key], None,
                             f"point {p}: {a} vs {b}, {coord}", log=False)
    _label_rd_grid(fig, axes, cs)
    return fig


def fig_rd_points(rd: Arrays, eig: Arrays, time: Mapping[str, Arrays], model: str,
                  coord: str) -> Figure:
    """Fig 3.32, 3.33, H.1-H.6: RD maps of evaluation points 1a, 1b, 1c, 2b, 3a, 3b.

    1a (NT vs NP) and 1b (LA vs NT) need the non-linear time solutions; they are drawn when
    present, otherwise the panel says so.
    """
    from ..evaluation import relative_difference

    fig, axes = plt.subplots(2, 3, figsize=(10, 5.8), sharex=True, sharey=True)
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
        cs = _rd_map(ax, v, w, r, eig, title)
    fig.suptitle(f"model {model}, {coord}: relative differences (Eq 3.26)", fontsize=9)
    _label_rd_grid(fig, axes, cs)
    _missing_note(fig, [m for m in ALL_TIME_METHODS if m in time])
    return fig


# --------------------------------------------------------------------------------------------
# one entry point for rules and notebooks: read results/ and draw a figure by id
# --------------------------------------------------------------------------------------------

def intermediate_path(kind: str, model: str = "", method: str = ""):
    """Where the linear rules write their arrays (``results/intermediate/...``)."""
    from .. import paths

    base = paths.intermediate()
    if kind == "eigen":
        return base / "eigen" / f"{model}.npz"
    if kind == "ps":
        return base / "ps" / f"{model}.npz"
    if kind == "time":
        return base / "time" / f"{method}_{model}.npz"
    if kind == "rd":
        return base / "rd" / f"{model}.npz"
    if kind == "pairs":
        return base / "rd" / "pairs.npz"
    raise ValueError(f"unknown kind {kind!r}")


def _load(path) -> dict:
    with np.load(path, allow_pickle=False) as d:
        return {k: d[k] for k in d.files}


def draw(fid: str, lin: Mapping, time_methods: Sequence[str] | None = None) -> Figure:
    """Draw figure ``fid`` of the linear part from the files under ``results/``.

    Parameters
    ----------
    fid
        A key of :data:`FIGURE_SPECS`.
    lin
        Values of config section ``linear`` the figures use: ``ps_*`` grid, ``eigen_speed_*``,
        ``harmonics``, ``gear_ratios``, ``normal_cycling_*``, ``reference_*`` (the rule passes
        exactly these as params; notebooks pass ``config.results_config()["linear"]``).
    time_methods
        Methods whose time-solution files to read; default: every method whose file exists.
    """
    from .. import disturbance, momentum
    from ..response import forcing, grid, select, speed_cadence_grid

    if fid not in FIGURE_SPECS:
        raise KeyError(f"{fid!r} is not a figure of the linear part")
    func, kw = FIGURE_SPECS[fid]

    def ps_grid():
        return speed_cadence_grid(lin["ps_speed_step_m_s"], lin["ps_speed_max_m_s"],
                                  lin["ps_omega_step_rad_s"], lin["ps_omega_max_rad_s"])
    models = spec_models(fid)
    needs = NEEDS[func]
    fn = globals()[func]

    def time_of(m):
        out = {}
        methods = time_methods if time_methods is not None else ALL_TIME_METHODS
        for meth in methods:
            p = intermediate_path("time", m, meth)
            if time_methods is not None or p.exists():
                out[meth] = _load(p)
        return out

    if func == "fig_gear_grid":
        v, w = ps_grid()
        return fn(v, w, lin["gear_ratios"], gears.wheel_radius_m("city"),
                  lin["normal_cycling_speed_kmh"], lin["normal_cycling_cadence_rpm"],
                  (lin["reference_speed_m_s"], lin["reference_cadence_rpm"] * np.pi / 30))
    if func == "fig_eigenvalues":
        return fn({m: _load(intermediate_path("eigen", m)) for m in models}, models)
    if func == "fig_cam_time":
        m = kw["model"]
        model = linear.linear_model(m)
        legs_all = disturbance.torque_harmonics(linear.bicycle_of(m),
                                                harmonics=tuple(range(1, 16, 2)))
        cases = {}
        for w0 in (2 * np.pi, 4 * np.pi):
            t = np.linspace(0, 2.0, 801)
            a, r = momentum.cam_time(model, legs_all, w0, t)
            cases[f"leg model, $\\omega$={w0 / np.pi:.0f}$\\pi$"] = dict(t_s=t, angle_rad=a,
                                                                         rate_rad_s=r)
        t = np.linspace(0, 2.0, 801)
        for label, h in (("cadence only", select(legs_all, (1,))),
                         ("roll torque only", select(legs_all, (1,), steer=False))):
            a, r = momentum.cam_time(model, h, 2 * np.pi, t)
            cases[f"{label}, $\\omega$=2$\\pi$"] = dict(t_s=t, angle_rad=a, rate_rad_s=r)
        return fn(cases, m)
    if func == "fig_neglected_momenta":
        m = kw["model"]
        v, w = ps_grid()
        ratios = momentum.neglected_momenta_ratios(linear.linear_model(m),
                                                   forcing(m, lin["harmonics"]),
                                                   v[:, None], w[None, :])
        return fn(v, w, ratios, m, gears.wheel_radius_m(linear.bicycle_of(m)),
                  (min(lin["gear_ratios"]), max(lin["gear_ratios"])))
    if func == "fig_amplitude_maps":
        ps = {m: _load(intermediate_path("ps", m)) for m in models}
        radius = {m: gears.wheel_radius_m(linear.bicycle_of(m)) for m in models}
        return fn(ps, models, radius, lin["normal_cycling_speed_kmh"],
                  lin["normal_cycling_cadence_rpm"],
                  (min(lin["gear_ratios"]), max(lin["gear_ratios"])))
    if func == "fig_gear_sections":
        v = grid(lin["eigen_speed_step_m_s"], lin["eigen_speed_max_m_s"])[1:]
        sections = {m: {gr: gear_section(m, forcing(m, lin["harmonics"]), gr,
                                         gears.wheel_radius_m(linear.bicycle_of(m)), v,
                                         lin["ps_omega_max_rad_s"])
                        for gr in lin["gear_ratios"]} for m in models}
        return fn(sections, models)
    if func == "fig_benchmark_ps":
        m = kw["model"]
        return fn(_load(intermediate_path("ps", m)), _load(intermediate_path("eigen", m)))
    if func == "fig_rd_reference":
        return fn({m: _load(intermediate_path("rd", m)) for m in models},
                  {m: _load(intermediate_path("eigen", m)) for m in models}, models)
    if func == "fig_rd_models":
        return fn(_load(intermediate_path("pairs")))
    m = kw["model"]
    args = []
    for need in needs:
        if need == "time":
            args.append(time_of(m))
        else:
            args.append(_load(intermediate_path(need, m)))
    return fn(*args, **kw)


def inputs_of(fid: str, results_dir: str, time_methods: Sequence[str]) -> list[str]:
    """Files a figure reads (for the Snakemake rule), under ``results_dir``."""
    func, kw = FIGURE_SPECS[fid]
    base = f"{results_dir}/intermediate"
    out = []
    for need in NEEDS[func]:
        for m in spec_models(fid):
            if need == "time":
                out += [f"{base}/time/{meth}_{m}.npz" for meth in time_methods]
            elif need == "pairs":
                continue
            else:
                out.append(f"{base}/{need}/{m}.npz")
        if need == "pairs":
            out.append(f"{base}/rd/pairs.npz")
    return out
