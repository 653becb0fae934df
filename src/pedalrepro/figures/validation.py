"""Figures 4.2-4.11: open-loop model vs treadmill measurement (Sec 4.2).

Each function takes arrays/DataFrames and returns a matplotlib Figure; the Snakemake rule saves
it and the notebook shows it. ``synthetic_reason`` (non-empty when the data are the synthetic
stand-in) stamps the figure SYNTHETIC with :func:`pedalrepro.figures.synthetic_stamp`. What
:mod:`pedalrepro.figures.registry` calls is named after the ids it draws (``fig_4_10``,
``fig_4_11``, ``real_run_panel``; ``figs_time_series`` and ``figs_frequency_domain`` for four
ids each): these take the loaded files (per-run table, measured series, data source, and the
model maps and series written by the rule ``validation_figure_data``,
:func:`pedalrepro.figdata.validation`) and hand the arrays to the drawing functions
(:func:`time_series`, :func:`frequency_domain`, :func:`run_amplitude_maps`,
:func:`run_relative_differences`, :func:`run_panel`), which a test or a notebook can call on
arrays of its own. Models are drawn in their chapter-3 colours
(:mod:`pedalrepro.figures.palette`). Figures 4.2-4.11 show only the build's main source
(``source.json``); the REAL public-subset run has its own, non-thesis panel,
``real_run_panel``, never pooled with them.
Figs 4.10 and 4.11 also show the CF system's published measurements, Moore's closed-loop
spectra (:mod:`pedalrepro.mocap.spectra`), as diamonds labelled "measured (published
spectra)": real data in every build, so a SYNTHETIC stamp says they are not part of it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from .. import spectral
from ..relative_difference import relative_difference
from .page import synthetic_stamp
from .palette import MEASURED_COLOUR, model_colour

__all__ = [
    "SYSTEM_FIGURES", "ExampleRun", "PSMap", "LEVELS", "time_series", "frequency_domain",
    "SPECTRA_LABEL", "SPECTRA_MARKER", "SpectraPoints", "run_amplitude_maps",
    "run_relative_differences", "SYSTEMS",
    "figs_time_series", "figs_frequency_domain", "fig_4_10", "fig_4_11",
    "run_panel", "no_real_run", "real_run_panel",
]

SYSTEM_FIGURES = {"HS": ("fig_4_2", "fig_4_6"), "CF": ("fig_4_3", "fig_4_7"),
                  "HR": ("fig_4_4", "fig_4_8"), "CR": ("fig_4_5", "fig_4_9")}


@dataclass
class ExampleRun:
    """One example run: measured and model (steady-state, crank-locked) angles."""

    run_id: int
    speed_kmh: float
    cadence_rpm: float
    t_s: np.ndarray
    roll_rad: np.ndarray
    steer_rad: np.ndarray
    model_roll_rad: np.ndarray
    model_steer_rad: np.ndarray


@dataclass
class PSMap:
    """Particular-solution amplitude map of a system (Sec 3.1.2.2.1)."""

    speed_m_s: np.ndarray
    omega_rad_s: np.ndarray
    roll_amp_rad: np.ndarray  # (n_v, n_w)
    steer_amp_rad: np.ndarray


#: Contour levels of log10 amplitude (rad), shared by every map so colours compare.
LEVELS = np.linspace(-4.0, -0.5, 15)


def _contour(ax, ps: PSMap, which: str, runs: Sequence[tuple[float, float]] | None = None):
    amp = ps.roll_amp_rad if which == "roll" else ps.steer_amp_rad
    amp = np.clip(amp, 10 ** LEVELS[0], 10 ** LEVELS[-1])
    cs = ax.contourf(ps.speed_m_s, ps.omega_rad_s, np.log10(amp).T, levels=LEVELS,
                     cmap="viridis")
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("cadence $\\omega$ (rad/s)")
    if runs:
        for i, (v, w) in enumerate(runs, start=1):
            ax.plot(v, w, "o", mfc="white", mec="k", ms=11)
            ax.text(v, w, str(i), ha="center", va="center", fontsize=8)
    return cs


def _stamp(fig: Figure, reason: str) -> None:
    if reason:
        synthetic_stamp(fig, reason)


def _example_grid(system: str, examples: Sequence[ExampleRun], ps: PSMap, coord: str):
    """Figure with the particular-solution ``coord`` map (top, the example runs numbered on it)
    and a grid of one row per example run, two columns (roll, steer) below; returns
    ``(fig, gridspec)``."""
    n = len(examples)
    fig = plt.figure(figsize=(7.0, 2.8 + 1.3 * n), layout="constrained")
    gs = fig.add_gridspec(n + 1, 2, height_ratios=[2.2] + [1] * n)
    ax = fig.add_subplot(gs[0, :])
    cs = _contour(ax, ps, coord, [(e.speed_kmh / 3.6, e.cadence_rpm * np.pi / 30)
                                  for e in examples])
    fig.colorbar(cs, ax=ax, label=f"log$_{{10}}$ {coord} amplitude (rad)")
    ax.set_title(f"system {system}: PS {coord} amplitude and example runs")
    return fig, gs


def _label_cell(a, i: int, j: int, n: int, ylabel: str, xlabel: str) -> None:
    """Small-print labels of the example-run cell in row ``i`` (of ``n``), column ``j``."""
    a.set_ylabel(ylabel, fontsize=8)
    a.tick_params(labelsize=8)
    if i == n - 1:
        a.set_xlabel(xlabel)
    if i == 0 and j == 0:
        a.legend(fontsize=8, loc="upper right")


def _signals(e: ExampleRun):
    """``(measured, model, name)`` for roll and steer of an example run."""
    return ((e.roll_rad, e.model_roll_rad, "roll"), (e.steer_rad, e.model_steer_rad, "steer"))


def time_series(system: str, examples: Sequence[ExampleRun], ps: PSMap,
                synthetic_reason: str = "", window_s: float = 10.0) -> Figure:
    """Figs 4.2-4.5: measured vs modelled roll (left) and steer (right) for example runs,
    numbered on the particular-solution roll map (top)."""
    n = len(examples)
    fig, gs = _example_grid(system, examples, ps, "roll")
    for i, e in enumerate(examples):
        sel = e.t_s <= e.t_s[0] + window_s
        for j, (meas, mod, name) in enumerate(_signals(e)):
            a = fig.add_subplot(gs[i + 1, j])
            a.plot(e.t_s[sel], meas[sel] - meas.mean(), lw=0.8, color=MEASURED_COLOUR,
                   label="measured")
            a.plot(e.t_s[sel], mod[sel], lw=1.0, color=model_colour(system),
                   label="model (open loop)")
            _label_cell(a, i, j, n, f"{i + 1}: {name} (rad)", "time (s)")
            a.set_title(f"{e.speed_kmh:g} km/h, {e.cadence_rpm:.0f} rpm", fontsize=8)
    _stamp(fig, synthetic_reason)
    return fig


def frequency_domain(system: str, examples: Sequence[ExampleRun], ps: PSMap,
                     sample_rate_hz: float, synthetic_reason: str = "") -> Figure:
    """Figs 4.6-4.9: Hann spectra of measured and modelled roll and steer (Sec 3.1.2.1.1)."""
    n = len(examples)
    fig, gs = _example_grid(system, examples, ps, "steer")
    for i, e in enumerate(examples):
        for j, (meas, mod, name) in enumerate(_signals(e)):
            a = fig.add_subplot(gs[i + 1, j])
            f, am = spectral.spectrum(meas - meas.mean(), sample_rate_hz, "hann")
            _, amod = spectral.spectrum(mod - mod.mean(), sample_rate_hz, "hann")
            keep = f <= 6 * e.cadence_rpm / 60
            a.semilogy(f[keep], am[keep], lw=0.8, color=MEASURED_COLOUR, label="measured")
            a.semilogy(f[keep], np.clip(amod[keep], 1e-7, None), lw=1.0,
                       color=model_colour(system), label="model")
            for k in (1, 2, 3):
                a.axvline(k * e.cadence_rpm / 60, color="grey", lw=0.5, ls=":")
            a.set_ylim(1e-6, None)
            _label_cell(a, i, j, n, f"{i + 1}: |{name}| (rad)", "frequency (Hz)")
    _stamp(fig, synthetic_reason)
    return fig


#: Label and marker of the measured closed-loop CF spectra's points in Figs 4.10-4.11.
SPECTRA_LABEL = "CF: measured (published spectra)"
SPECTRA_MARKER = "D"


@dataclass
class SpectraPoints:
    """The measured CF spectra's cadence amplitudes and the open-loop CF model at the same
    speeds and cadences (:func:`pedalrepro.figdata.validation`, keys ``spectra_*``)."""

    speed_kmh: np.ndarray
    cadence_rpm: np.ndarray
    roll_measured_rad: np.ndarray
    steer_measured_rad: np.ndarray
    roll_model_rad: np.ndarray
    steer_model_rad: np.ndarray

    @classmethod
    def from_arrays(cls, model: dict) -> SpectraPoints | None:
        """The points in ``model`` (the figure-data file), or None when the build has none."""
        if "spectra_speed_kmh" not in model:
            return None
        return cls(*(np.asarray(model[f"spectra_{k}"], float) for k in (
            "speed_kmh", "cadence_rpm", "roll_measured_rad", "steer_measured_rad",
            "roll_model_rad", "steer_model_rad")))

    def measured(self, q: str) -> np.ndarray:
        return self.roll_measured_rad if q == "roll" else self.steer_measured_rad

    def model(self, q: str) -> np.ndarray:
        return self.roll_model_rad if q == "roll" else self.steer_model_rad

    def rd_percent(self, q: str) -> np.ndarray:
        """Relative difference of the open-loop model from the measurement (Eq 3.26)."""
        return relative_difference(self.measured(q), self.model(q))


def _spectra_note(reason: str, spectra: SpectraPoints | None) -> str:
    """The SYNTHETIC stamp's reason, saying the diamonds are real measurements."""
    if reason and spectra is not None:
        return (f"{reason}; the diamonds ({SPECTRA_LABEL}) are real measurements, not the "
                "stand-in")
    return reason


def run_amplitude_maps(per_run: pd.DataFrame, maps: dict[str, PSMap], synthetic_reason: str = "",
             spectra: SpectraPoints | None = None, runs_label: str = "runs") -> Figure:
    """Fig 4.10: every run as a circle on the particular-solution map of its system; fill =
    measured amplitude, edge = model / measured ratio. ``spectra``: the measured CF spectra's
    points, drawn as diamonds on the CF maps with the same fill and edge scales."""
    systems = list(maps)
    fig, axes = plt.subplots(len(systems), 2, figsize=(7.0, 1.6 + 2.2 * len(systems)),
                             squeeze=False, sharex=True, sharey=True, layout="constrained")
    norm = plt.Normalize(-3, -1)
    rnorm = plt.Normalize(-1, 1)

    def points(ax, v_m_s, w_rad_s, measured, model, marker, label):
        return ax.scatter(v_m_s, w_rad_s, c=np.log10(measured), cmap="magma", norm=norm,
                          s=60, marker=marker, linewidths=2.0, label=label,
                          edgecolors=plt.cm.coolwarm(rnorm(np.log10(model / measured))))

    for j, system in enumerate(systems):
        sub = per_run[per_run.system == system]
        for i, q in enumerate(("roll", "steer")):
            ax = axes[j, i]
            _contour(ax, maps[system], q)
            sc = points(ax, sub.speed_kmh / 3.6, sub.cadence_rpm * np.pi / 30,
                        sub[f"{q}_measured_rad"], sub[f"{q}_model_rad"], "o", runs_label)
            if system == "CF" and spectra is not None:
                points(ax, spectra.speed_kmh / 3.6, spectra.cadence_rpm * np.pi / 30,
                       spectra.measured(q), spectra.model(q), SPECTRA_MARKER, SPECTRA_LABEL)
                if i == 0:
                    ax.legend(loc="upper left", fontsize=8, framealpha=0.8)
            ax.set_title(f"{system} {q}", fontsize=9)
            ax.set_xlabel("")
            if i:
                ax.set_ylabel("")
    for ax in axes[-1]:
        ax.set_xlabel("forward speed v (m/s)")
    for mappable, label in (
            (plt.cm.ScalarMappable(plt.Normalize(LEVELS[0], LEVELS[-1]), "viridis"),
             "map: log$_{10}$ model amplitude (rad)"),
            (sc, "fill: log$_{10}$ measured amplitude (rad)"),
            (plt.cm.ScalarMappable(rnorm, "coolwarm"), "edge: log$_{10}$(model / measured)")):
        fig.colorbar(mappable, ax=axes, location="bottom", shrink=0.8, aspect=40, pad=0.01,
                     label=label)
    _stamp(fig, _spectra_note(synthetic_reason, spectra))
    return fig


def run_relative_differences(per_run: pd.DataFrame, synthetic_reason: str = "",
             spectra: SpectraPoints | None = None) -> Figure:
    """Fig 4.11: relative difference model vs measurement of every run, per system;
    ``spectra``: the open-loop CF model against the measured CF spectra, as diamonds."""
    fig, axes = plt.subplots(1, 2, figsize=(7.0, 3.6), sharey=True, layout="constrained")
    for q, ax in zip(("roll", "steer"), axes, strict=True):
        for system, sub in per_run.groupby("system", sort=False):
            ax.plot(sub.speed_kmh, sub[f"{q}_rd_percent"], "o", label=system,
                    color=model_colour(str(system)))
        if spectra is not None:
            ax.plot(spectra.speed_kmh, spectra.rd_percent(q), SPECTRA_MARKER, mfc="none",
                    mew=1.5, color=model_colour("CF"), label=SPECTRA_LABEL)
        ax.set_yscale("log")
        ax.set_xlabel("belt speed (km/h)")
        ax.set_title(f"{q}: RD model vs measurement")
    axes[0].set_ylabel("RD (%)")
    axes[1].legend(fontsize=8)
    _stamp(fig, _spectra_note(synthetic_reason, spectra))
    return fig


# --------------------------------------------------------------------------------------------
# entry points of the figure registry: loaded files in, a Figure out
# --------------------------------------------------------------------------------------------

#: The systems of the model maps, in the order of :data:`SYSTEM_FIGURES` (the thesis's four,
#: pedalrepro.params.MODELS; not imported: this module stays free of the parameter files, so the
#: validation figures do not rerun when one changes; tests/test_params.py pins the two equal).
SYSTEMS: tuple[str, ...] = tuple(SYSTEM_FIGURES)


def _reason(source: dict) -> str:
    return "" if source["data_source"] == "figshare" else source["reason"]


def _main(per_run: pd.DataFrame, source: dict) -> pd.DataFrame:
    """The rows of the build's main source only: real public-subset rows (their own
    ``data_source``) are never pooled into the synthetic or figshare figures."""
    if "data_source" not in per_run:
        return per_run
    return per_run[per_run.data_source == source["data_source"]]


def _maps(model: dict) -> dict[str, PSMap]:
    return {s: PSMap(model["speed_m_s"], model["omega_rad_s"], model[f"{s}_roll_amp_rad"],
                     model[f"{s}_steer_amp_rad"]) for s in SYSTEMS if f"{s}_roll_amp_rad" in model}


def _examples(per_run: pd.DataFrame, series: dict, model: dict, system: str) -> list[ExampleRun]:
    out = []
    for k, rid in enumerate(np.atleast_1d(model[f"{system}_run_ids"])):
        row = per_run[per_run.run_id == rid].iloc[0]
        out.append(ExampleRun(int(rid), float(row.speed_kmh), float(row.cadence_rpm),
                              series[f"{rid}_t_s"], series[f"{rid}_roll_rad"],
                              series[f"{rid}_steer_rad"], model[f"{system}_{k}_roll_rad"],
                              model[f"{system}_{k}_steer_rad"]))
    return out


def figs_time_series(per_run, series, source, model, system: str) -> Figure:
    """Figs 4.2-4.5 from the registry's files, one system each: ``fig_4_2`` (HS),
    ``fig_4_3`` (CF), ``fig_4_4`` (HR), ``fig_4_5`` (CR); drawn by :func:`time_series`."""
    return time_series(system, _examples(_main(per_run, source), series, model, system),
                       _maps(model)[system],
                       _reason(source))


def figs_frequency_domain(per_run, series, source, model, system: str) -> Figure:
    """Figs 4.6-4.9 from the registry's files, one system each: ``fig_4_6`` (HS),
    ``fig_4_7`` (CF), ``fig_4_8`` (HR), ``fig_4_9`` (CR); drawn by :func:`frequency_domain`."""
    ex = _examples(_main(per_run, source), series, model, system)
    fs = float(1.0 / np.median(np.diff(ex[0].t_s)))
    return frequency_domain(system, ex, _maps(model)[system], fs, _reason(source))


def _runs_label(source: dict) -> str:
    return "treadmill runs" if source["data_source"] == "figshare" else "SYNTHETIC runs"


def fig_4_10(per_run, series, source, model) -> Figure:
    """Fig 4.10 from the registry's files (the CF spectra's points from the figure data),
    drawn by :func:`run_amplitude_maps`."""
    return run_amplitude_maps(_main(per_run, source), _maps(model), _reason(source),
                    SpectraPoints.from_arrays(model), _runs_label(source))


def fig_4_11(per_run, series, source, model) -> Figure:
    """Fig 4.11 from the registry's files (the CF spectra's points from the figure data),
    drawn by :func:`run_relative_differences`."""
    return run_relative_differences(_main(per_run, source), _reason(source),
                                    SpectraPoints.from_arrays(model))


def run_panel(run: ExampleRun, system: str, data_label: str, window_s: float = 10.0
                   ) -> Figure:
    """A Fig 4.2/4.6-style panel of one REAL run (public subset): measured vs open-loop model
    roll and steer over ``window_s`` (top) and their Hann amplitude spectra (bottom), with the
    cadence, the Hann bin nearest it (the thesis's amplitude, o) and the DFT at the exact cadence
    (this project's, x) marked. ``data_label`` is printed in the title (e.g. ``REAL run
    3045``)."""
    fs = float(1.0 / np.median(np.diff(run.t_s)))
    fc = run.cadence_rpm / 60.0
    fig, axes = plt.subplots(2, 2, figsize=(7.0, 5.6), layout="constrained")
    sel = run.t_s <= run.t_s[0] + window_s
    for j, (meas, mod, name) in enumerate(_signals(run)):
        a = axes[0, j]
        a.plot(run.t_s[sel], meas[sel], "k-", lw=0.9, label="measured")
        a.plot(run.t_s[sel], mod[sel], "C1--", lw=1.1, label="model (particular solution)")
        a.set_xlabel("time (s)")
        a.set_ylabel(f"{name} (rad)")
        b = axes[1, j]
        x = meas - meas.mean()
        f, amp = spectral.spectrum(x, fs, "hann")
        keep = f <= 4.0 * fc
        b.semilogy(f[keep], amp[keep], "k-", lw=0.8, label="measured, Hann")
        fm, am = spectral.spectrum(mod - mod.mean(), fs, "hann")
        b.semilogy(fm[keep], am[keep], "C1--", lw=0.9, label="model, Hann")
        k = int(np.argmin(np.abs(f - fc)))
        b.plot(f[k], amp[k], "o", mfc="none", mec="C0", label="nearest bin (thesis)")
        b.plot(fc, spectral.amplitude_at(x, fs, fc), "x", color="C3",
               label="exact cadence (project)")
        for h in (1, 2, 3):
            b.axvline(h * fc, color="0.6", ls=":", lw=0.8)
        b.set_xlabel("frequency (Hz)")
        b.set_ylabel(f"|{name}| (rad)")
    axes[0, 0].legend(fontsize=8, loc="upper right")
    axes[1, 0].legend(fontsize=8, loc="upper right")
    fig.suptitle(f"{data_label}: system {system}, {run.speed_kmh:.1f} km/h, "
                 f"{run.cadence_rpm:.2f} rpm (measurement, not synthetic)", fontsize=9)
    return fig


def no_real_run(text: str) -> Figure:
    """The REAL-run panel's stand-in when a build has no real run: a figure that says so."""
    fig, ax = plt.subplots(figsize=(7.0, 1.6))
    ax.axis("off")
    ax.text(0.5, 0.5, text, ha="center", va="center", wrap=True, fontsize=10)
    return fig


def real_run_panel(source, model) -> Figure:
    """The REAL run's panel (not a thesis figure) from the registry's files: the real
    public-subset run that :func:`pedalrepro.figdata.validation` wrote into ``model``
    (keys ``real_*``), drawn by :func:`run_panel`, or a figure saying the build has none
    (:func:`no_real_run`)."""
    if "real_run_id" not in model:
        return no_real_run("No real public-subset run in this build (data_source: "
                           f"{source['data_source']}; see the chapter's data note)")
    run = ExampleRun(int(model["real_run_id"]), float(model["real_speed_kmh"]),
                     float(model["real_cadence_rpm"]), model["real_t_s"], model["real_roll_rad"],
                     model["real_steer_rad"], model["real_model_roll_rad"],
                     model["real_model_steer_rad"])
    return run_panel(run, str(model["real_system"]), f"REAL run {run.run_id}")
