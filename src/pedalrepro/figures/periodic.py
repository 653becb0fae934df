"""Figures of the periodic orbits of the non-linear models (beyond the thesis, issue 14).

Inputs are the arrays written by :mod:`pedalrepro.periodic` (``results/intermediate/periodic``)
and the NT/NP simulation sweeps (``results/intermediate/time/<method>_<model>.npz``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

AMP_NORM = (1e-4, 1.0)  # rad, colour range of the amplitude maps
RD_NORM = (1e-3, 1e2)   # percent


def _mesh(ax, v, w, z, norm, cmap="viridis"):
    z = np.where(np.isfinite(z) & (z > 0), z, np.nan)
    return ax.pcolormesh(v, w, np.clip(z, *norm).T, norm=LogNorm(*norm), cmap=cmap,
                         shading="nearest")


def _unstable(ax, v, w, stable, converged) -> None:
    """Hatch the grid cells whose orbit is unstable (or did not converge: cross-hatched)."""
    forced = w[None, :] > 0
    unstable = (~np.asarray(stable, bool)) & np.asarray(converged, bool) & forced
    failed = ~np.asarray(converged, bool) & forced
    for mask, hatch in ((unstable, "///"), (failed, "xxx")):
        if mask.any():
            ax.contourf(v, w, mask.T.astype(float), levels=[0.5, 1.5], colors="none",
                        hatches=[hatch])
    if unstable.any() and (~unstable & forced).any():
        ax.contour(v, w, unstable.T.astype(float), levels=[0.5], colors="w", linewidths=1.0)


def _axes_labels(axes) -> None:
    for ax in axes[-1, :]:
        ax.set_xlabel("forward speed v (m/s)")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"cadence $\omega$ (rad/s)")


def fig_orbit_maps(orbits: Mapping[str, Mapping], sims: Mapping[str, Mapping], model: str,
                   methods: Sequence[str] = ("NT", "NP")) -> plt.Figure:
    """Cadence amplitude maps of one model: PS, periodic orbit, simulation, and their RD.

    Rows: ``<method> roll``, ``<method> steer``. Columns: the particular solution of the
    model's own linearisation (PS); the periodic orbit by shooting, hatched where unstable
    (``///``: a Floquet multiplier outside the unit circle; ``xxx``: no convergence); the
    thesis's method (DFT of a simulation; shown only where the orbit is stable, runs that fell
    marked ``x``); RD (Eq 3.26) of the simulation from the orbit, percent, stable orbits only.

    Parameters
    ----------
    orbits, sims
        Keyed by method: the ``periodic/thesis_<method>_<model>.npz`` and the
        ``time/<method>_<model>.npz`` arrays (same grid).
    """
    rows = [(m, c) for m in methods for c in ("roll", "steer")]
    fig, axes = plt.subplots(len(rows), 4, figsize=(13, 2.7 * len(rows)), sharex=True,
                             sharey=True, squeeze=False)
    amp_mesh = rd_mesh = None
    for i, (method, coord) in enumerate(rows):
        o, s = orbits[method], sims.get(method)
        v, w = np.asarray(o["speed_m_s"]), np.asarray(o["omega_rad_s"])
        stable = np.asarray(o["stable"], bool)
        orbit_amp = np.asarray(o[f"{coord}_amp_rad"], float)
        amp_mesh = _mesh(axes[i, 0], v, w, np.asarray(o[f"ps_{coord}_amp_rad"]), AMP_NORM)
        _mesh(axes[i, 1], v, w, orbit_amp, AMP_NORM)
        _unstable(axes[i, 1], v, w, stable, o["converged"])
        if s is not None:
            sim_amp = np.where(stable, np.asarray(s[f"{coord}_amp_rad"], float), np.nan)
            _mesh(axes[i, 2], v, w, sim_amp, AMP_NORM)
            fell = np.asarray(s["fell"], bool)
            vv, ww = np.meshgrid(v, w, indexing="ij")
            axes[i, 2].plot(vv[fell], ww[fell], "x", color="0.3", ms=3)
            with np.errstate(divide="ignore", invalid="ignore"):
                rd = np.abs(sim_amp - orbit_amp) / orbit_amp * 100.0
            rd_mesh = _mesh(axes[i, 3], v, w, rd, RD_NORM, cmap="magma")
        else:
            for ax in axes[i, 2:]:
                ax.text(0.5, 0.5, "no simulation", transform=ax.transAxes, ha="center")
        for j, name in enumerate(("PS (own linearisation)", "periodic orbit",
                                  "simulation (stable orbits)", "RD simulation vs orbit")):
            axes[i, j].set_title(f"{model} {method} {coord}: {name}", fontsize=8)
    _axes_labels(axes)
    fig.colorbar(amp_mesh, ax=axes[:, :3], label="cadence amplitude (rad)", shrink=0.6,
                 location="bottom", aspect=40)
    if rd_mesh is not None:
        fig.colorbar(rd_mesh, ax=axes[:, 3], label="RD (%)", shrink=0.9, location="bottom",
                     aspect=15)
    return fig


def fig_fine_maps(fine: Mapping[str, Mapping], method: str = "NT") -> plt.Figure:
    """Orbit amplitude maps of every model on the finer grid; unstable orbits hatched."""
    models = list(fine)
    fig, axes = plt.subplots(2, len(models), figsize=(3.3 * len(models), 5.8), sharex=True,
                             sharey=True, squeeze=False)
    mesh = None
    for j, model in enumerate(models):
        d = fine[model]
        v, w = np.asarray(d["speed_m_s"]), np.asarray(d["omega_rad_s"])
        for i, coord in enumerate(("roll", "steer")):
            mesh = _mesh(axes[i, j], v, w, np.asarray(d[f"{coord}_amp_rad"], float), AMP_NORM)
            _unstable(axes[i, j], v, w, d["stable"], d["converged"])
            axes[i, j].set_title(f"{model} {method} {coord}", fontsize=9)
    _axes_labels(axes)
    fig.colorbar(mesh, ax=axes, label="cadence amplitude of the orbit (rad)", shrink=0.8)
    return fig


def fig_continuation(branches: Mapping[str, Mapping]) -> plt.Figure:
    """Continuation diagram at the reference cadence: roll amplitude and the largest Floquet
    multiplier modulus along each branch (solid: stable, dashed: unstable, markers: multiplier
    crossings), the linear-limit branch scaled back to full torque (dotted), and the self-stable
    speeds of the model's own linearisation (shaded)."""
    models = list(branches)
    fig, axes = plt.subplots(2, len(models), figsize=(3.4 * len(models), 5.6), sharex=True,
                             squeeze=False)
    colors = {"NT": "C0", "NP": "C1"}
    for j, model in enumerate(models):
        b = branches[model]
        scales = np.atleast_1d(b["torque_scales"])
        for method in [str(m) for m in np.atleast_1d(b["methods"])]:
            for k, scale in enumerate(scales):
                key = f"{method}_{k}_"
                if f"{key}values" not in b:
                    continue
                v = np.asarray(b[f"{key}values"])
                amp = np.asarray(b[f"{key}roll_amp_rad"]) / scale
                mu = np.max(np.abs(np.asarray(b[f"{key}multipliers"])), axis=1)
                st = np.asarray(b[f"{key}stable"], bool)
                label = f"{method}" if scale == 1 else f"{method} x{scale:g} (/{scale:g})"
                style = ":" if scale != 1 else "-"
                for ax, y in ((axes[0, j], amp), (axes[1, j], mu)):
                    ax.plot(v, np.where(st, y, np.nan), style, color=colors.get(method, "k"),
                            label=label if ax is axes[0, j] else None)
                    ax.plot(v, np.where(st, np.nan, y), "--" if scale == 1 else ":",
                            color=colors.get(method, "k"), alpha=0.6)
                for c in np.asarray(b[f"{key}crossing_values"]):
                    axes[1, j].plot(c, 1.0, "o", mfc="none", color=colors.get(method, "k"))
        for lo, hi in np.asarray(b["linear_stable_ranges_m_s"]).reshape(-1, 2):
            for ax in axes[:, j]:
                ax.axvspan(lo, hi, color="0.85", lw=0, zorder=0)
        axes[0, j].set_title(f"{model}, {float(b['cadence_rpm']):g} rpm", fontsize=9)
        axes[0, j].set_yscale("log")
        axes[1, j].set_yscale("log")
        axes[1, j].axhline(1.0, color="k", lw=0.6)
        axes[1, j].set_xlabel("forward speed v (m/s)")
    axes[0, 0].set_ylabel("roll amplitude (rad)")
    axes[1, 0].set_ylabel("max |Floquet multiplier|")
    axes[0, 0].legend(fontsize=7)
    return fig


def _by_name(files, prefix: str) -> dict[str, dict]:
    """``{stem without prefix: arrays}`` of ``.npz`` files (e.g. ``thesis_NT_HR``)."""
    from pathlib import Path

    out = {}
    for f in files:
        stem = Path(f).stem
        if stem.startswith(prefix):
            out[stem[len(prefix):]] = dict(np.load(f))
    return out


def draw_all(inputs, outputs: Sequence[str], models: Sequence[str],
             methods: Sequence[str]) -> None:
    """Draw and save every figure of ``rules/periodic.smk``: ``periodic_maps_<model>``,
    ``periodic_continuation`` and (with fine maps) ``periodic_fine_maps``, matched to
    ``outputs`` by file name."""
    from pathlib import Path

    from . import save, style

    maps = _by_name(inputs.maps, "thesis_")
    fine = _by_name(inputs.fine, "fine_")
    sims = {Path(f).stem: dict(np.load(f)) for f in inputs.time}
    branches = {str(np.load(f)["model"]): dict(np.load(f)) for f in inputs.branches}
    named = {Path(p).stem: p for p in outputs}
    with style():
        for model in models:
            fig = fig_orbit_maps({m: maps[f"{m}_{model}"] for m in methods},
                                 {m: sims[f"{m}_{model}"] for m in methods
                                  if f"{m}_{model}" in sims}, model, methods)
            save(fig, named[f"periodic_maps_{model}"])
        save(fig_continuation({m: branches[m] for m in models}),
             named["periodic_continuation"])
        if "periodic_fine_maps" in named:
            method = next(iter(fine)).split("_")[0]
            save(fig_fine_maps({m: fine[f"{method}_{m}"] for m in models
                                if f"{method}_{m}" in fine}, method),
                 named["periodic_fine_maps"])
