"""Figures of the rider's closed loop (beyond the thesis; :mod:`pedalrepro.rider`).

Inputs are the files of ``rules/closed_loop.smk``: ``closed_loop_validation.csv`` (open loop vs
closed loop vs measurement), ``intermediate/closed_loop/eigen.npz`` (rule gains and closed-loop
eigenvalues against speed) and ``intermediate/closed_loop/spectra.npz`` (the measured spectra).
Drawing only reads them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from .palette import MEASURED_COLOUR, MODEL_COLOURS

__all__ = ["closed_loop_validation", "closed_loop_gains", "closed_loop_maps", "closed_loop_time",
           "draw_all"]

_OPEN = dict(color="0.45", ls="--", marker="s", ms=4, lw=1.0)
_CLOSED = dict(ls="-", marker="o", ms=4, lw=1.2)


def closed_loop_validation(validation: pd.DataFrame) -> plt.Figure:
    """Cadence amplitudes against speed: measured, open-loop model, closed-loop model.

    Left: CF against Moore's measured spectra ("measured (published spectra)"); right: HR and
    CR against Table 4.1's printed measured values (and the real run). Open symbols: the closed
    loop is unstable there (its particular solution is not a steady state).
    """
    fig, axes = plt.subplots(2, 2, figsize=(7.0, 5.6), sharex="col", constrained_layout=True)
    for col, systems in enumerate((("CF",), ("HR", "CR"))):
        for row, q in enumerate(("roll", "steer")):
            ax = axes[row, col]
            for system in systems:
                sub = validation[(validation.system == system) & (validation.quantity == q)]
                colour = MODEL_COLOURS.get(system, "k")
                for source, s in sub.groupby("source", sort=False):
                    s = s.sort_values("speed_kmh")
                    marker = "x" if source.startswith("run") else "D"
                    ax.plot(s.speed_kmh, s.measured_rad, ls="none", marker=marker, ms=5,
                            color=MEASURED_COLOUR, mfc="none" if system == "CR" else None,
                            label=f"measured {system}: {source.split(' (')[0]}")
                s = sub.drop_duplicates("speed_kmh").sort_values("speed_kmh")
                ax.plot(s.speed_kmh, s.open_loop_rad, label=f"open loop {system}", **_OPEN)
                ax.plot(s.speed_kmh, s.closed_loop_rad, color=colour,
                        label=f"closed loop {system}", **_CLOSED)
                un = s[~s.closed_loop_stable.astype(bool)]
                ax.plot(un.speed_kmh, un.closed_loop_rad, ls="none", marker="o", ms=7,
                        mfc="w", mec=colour)
            ax.set_yscale("log")
            ax.set_ylabel(f"{q} amplitude at cadence (rad)")
            ax.grid(True, which="both", alpha=0.3)
        axes[1, col].set_xlabel("belt speed (km/h)")
    axes[0, 0].set_title("CF: measured spectra", fontsize=9)
    axes[0, 1].set_title("HR, CR: Table 4.1 measured", fontsize=9)
    for ax in axes[0]:
        ax.legend(fontsize=8, loc="best")
    return fig


def closed_loop_gains(eigen: Mapping[str, np.ndarray], models: Sequence[str] | None = None
              ) -> plt.Figure:
    """Rule gains ``kDelta`` (N m/rad) and ``kPhi`` and the largest real part of the
    closed-loop eigenvalues against speed, per model."""
    models = list(models if models is not None else [str(m) for m in eigen["models"]])
    fig, axes = plt.subplots(1, 3, figsize=(7.0, 2.8), constrained_layout=True)
    for m in models:
        v = eigen[f"{m}_speed_m_s"]
        g = eigen[f"{m}_gains"]
        colour = MODEL_COLOURS.get(m, "#9467bd")
        axes[0].plot(v, g[:, 0], color=colour, label=m)
        axes[1].plot(v, g[:, 2], color=colour, label=m)
        axes[2].plot(v, eigen[f"{m}_eigenvalues"].real.max(axis=1), color=colour, label=m)
    axes[0].set_ylabel("kDelta (N m/rad)")
    axes[1].set_ylabel("kPhi (-)")
    axes[2].set_ylabel("max Re(eigenvalue) (1/s)")
    axes[2].axhline(0.0, color="k", lw=0.8)
    for ax in axes:
        ax.set_xlabel("speed (m/s)")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    return fig


def closed_loop_maps(maps: Mapping[str, Mapping[str, np.ndarray]]) -> plt.Figure:
    """Closed-loop cadence amplitude maps (roll, steer) over speed and cadence per model, as a
    ratio to the open loop's (PS): below 1 the rider reduces the pedalling response. Speeds where
    the closed loop is unstable (or has no gains) are greyed out."""
    from matplotlib.colors import LogNorm

    models = list(maps)
    fig, axes = plt.subplots(2, len(models), figsize=(7.0, 4.2), sharex=True, sharey=True,
                             constrained_layout=True, squeeze=False)
    norm = LogNorm(0.1, 10.0)
    mesh = None
    for j, m in enumerate(models):
        d = maps[m]
        v, w = d["speed_m_s"], d["omega_rad_s"]
        for i, q in enumerate(("roll", "steer")):
            ax = axes[i, j]
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = d[f"{q}_amp_rad"] / d[f"open_{q}_amp_rad"]
            ratio = np.where(np.asarray(d["stable"], bool)[:, None] & np.isfinite(ratio)
                             & (ratio > 0), ratio, np.nan)
            mesh = ax.pcolormesh(v, w, np.clip(ratio, 0.1, 10.0).T, norm=norm, cmap="RdBu_r",
                                 shading="nearest")
            ax.set_facecolor("0.85")
            ax.set_title(f"{m} {q}", fontsize=9)
            if j == 0:
                ax.set_ylabel("cadence (rad/s)")
            if i == 1:
                ax.set_xlabel("speed (m/s)")
    fig.colorbar(mesh, ax=axes, shrink=0.8, label="closed / open loop amplitude")
    return fig


def closed_loop_time(series: Mapping[str, np.ndarray]) -> plt.Figure:
    """CF roll and steer from rest, open loop (LA) and closed loop, at the example speeds (the
    axis spans three times the closed loop's largest value: the unstable open loop leaves it)."""
    t = series["t_s"]
    keys = sorted({k.removesuffix("_closed_roll_rad") for k in series
                   if k.endswith("_closed_roll_rad")}, key=lambda k: float(k.split("_")[1]))
    if not keys:  # the measured spectra (their speeds and cadences) are not in this build
        fig, ax = plt.subplots(figsize=(7.0, 1.5))
        ax.axis("off")
        ax.text(0.5, 0.5, "No CF example: the measured spectra are not in this build's data "
                "folder", ha="center", va="center", fontsize=9)
        return fig
    fig, axes = plt.subplots(len(keys), 2, figsize=(7.0, 1.6 + 1.5 * len(keys)), sharex=True,
                             constrained_layout=True, squeeze=False)
    for i, key in enumerate(keys):
        for j, q in enumerate(("roll", "steer")):
            ax = axes[i, j]
            ax.plot(t, series[f"{key}_open_{q}_rad"], color="0.45", ls="--", lw=1.0,
                    label="open loop (LA)")
            ax.plot(t, series[f"{key}_closed_{q}_rad"], color=MODEL_COLOURS["CF"], lw=1.1,
                    label="closed loop")
            # the unstable open loop grows without bound: the axis follows the closed loop
            lim = 3.0 * np.nanmax(np.abs(series[f"{key}_closed_{q}_rad"]))
            ax.set_ylim(-lim, lim)
            ax.set_title(f"CF {key.split('_')[1]} km/h, "
                         f"{float(series[f'{key}_cadence_rpm']):.0f} rpm: {q}", fontsize=9)
            ax.set_ylabel(f"{q} (rad)")
            ax.grid(True, alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes[0, 0].legend(fontsize=8)
    return fig


def draw_all(inputs, outputs: Sequence[str]) -> None:
    """Draw and save the figures of ``rules/closed_loop.smk`` (matched to ``outputs`` by name)."""
    from pathlib import Path

    from . import save, style

    named = {Path(p).stem: p for p in outputs}
    with style():
        save(closed_loop_validation(pd.read_csv(inputs.validation)),
             named["closed_loop_validation"])
        save(closed_loop_gains(dict(np.load(inputs.eigen))), named["closed_loop_gains"])
        maps = {str(Path(f).stem).removeprefix("map_"): dict(np.load(f)) for f in inputs.maps}
        save(closed_loop_maps(maps), named["closed_loop_maps"])
        save(closed_loop_time(dict(np.load(inputs.time))), named["closed_loop_time"])
