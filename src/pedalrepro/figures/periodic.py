"""Figures of the periodic orbits of the non-linear models (beyond the thesis).

Inputs are the arrays written by :mod:`pedalrepro.periodic` (``results/intermediate/periodic``)
and the NT/NP simulation sweeps (``results/intermediate/time/<method>_<model>.npz``). Registered
in :mod:`pedalrepro.figures.registry` (part and group ``periodic``) like every other figure.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

__all__ = ["AMP_NORM", "RD_NORM", "figs_orbit_maps", "periodic_fine_maps", "periodic_continuation"]

AMP_NORM = (1e-4, 1.0)  # rad, colour range of the amplitude maps
RD_NORM = (1e-3, 1e2)   # percent


def _mesh(ax, v, w, z, norm, cmap="viridis"):
    z = np.where(np.isfinite(z) & (z > 0), z, np.nan)
    z = np.clip(z, *norm).T
    dv, dw = np.diff(v), np.diff(w)
    if v.size > 1 and w.size > 1 and np.allclose(dv, dv[0]) and np.allclose(dw, dw[0]):
        # a uniform grid: one image, cell centres at the grid points (as pcolormesh's
        # "nearest" shading), embedded at its own resolution: the PDFs are a third smaller
        # than with a rasterized mesh (figure-sized rasters); the drawing time is the same
        # (16.2 vs 16.5 s for the six periodic figures: constrained layout of 20 axes)
        return ax.imshow(z, norm=LogNorm(*norm), cmap=cmap, origin="lower", aspect="auto",
                         interpolation="nearest",
                         extent=(v[0] - dv[0] / 2, v[-1] + dv[0] / 2, w[0] - dw[0] / 2,
                                 w[-1] + dw[0] / 2))
    return ax.pcolormesh(v, w, z, norm=LogNorm(*norm), cmap=cmap, shading="nearest",
                         rasterized=True)


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


def figs_orbit_maps(orbits: Mapping[str, Mapping], model: str,
                   methods: Sequence[str] = ("NT", "NP"),
                   sims: Mapping[str, Mapping] | None = None) -> plt.Figure:
    """Cadence amplitude maps of one model: PS, periodic orbit, simulation, and their RD;
    ``periodic_maps_HS``, ``periodic_maps_CF``, ``periodic_maps_HR``, ``periodic_maps_CR``.

    Columns: roll, steer. Rows, for each method: the particular solution of the model's own
    linearisation (PS); the periodic orbit by shooting, hatched where unstable (``///``: a
    Floquet multiplier outside the unit circle; ``xxx``: no convergence); the thesis's method
    (DFT of a simulation; shown only where the orbit is stable, runs that fell marked ``x``);
    RD (Eq 3.26) of the simulation from the orbit, percent, stable orbits only. Drawn in rows so
    that the figure fits the book's content width.

    Parameters
    ----------
    orbits, sims
        Keyed by method: the ``periodic/thesis_<method>_<model>.npz`` and the
        ``time/<method>_<model>.npz`` arrays (same grid); a method without simulation says so.

    Notes
    -----
    Each method's block of four rows has its own two colour bars on the right, beside the rows
    they belong to: amplitude (rad) beside the three amplitude rows, RD (%) beside the RD row.
    """
    panels = ("PS (own linearisation)", "periodic orbit", "simulation (stable orbits)",
              "RD simulation vs orbit")
    fig, axes = plt.subplots(len(methods) * len(panels), 2,
                             figsize=(7.0, 1.75 * len(methods) * len(panels) + 1.2),
                             sharex=True, sharey=True, squeeze=False, layout="constrained")
    sims = sims or {}
    for a, method in enumerate(methods):
        o, s = orbits[method], sims.get(method)
        amp_mesh = rd_mesh = None
        v, w = np.asarray(o["speed_m_s"]), np.asarray(o["omega_rad_s"])
        stable = np.asarray(o["stable"], bool)
        for j, coord in enumerate(("roll", "steer")):
            ax_ps, ax_orbit, ax_sim, ax_rd = (axes[a * len(panels) + k, j] for k in range(4))
            orbit_amp = np.asarray(o[f"{coord}_amp_rad"], float)
            amp_mesh = _mesh(ax_ps, v, w, np.asarray(o[f"ps_{coord}_amp_rad"]), AMP_NORM)
            _mesh(ax_orbit, v, w, orbit_amp, AMP_NORM)
            _unstable(ax_orbit, v, w, stable, o["converged"])
            if s is not None:
                sim_amp = np.where(stable, np.asarray(s[f"{coord}_amp_rad"], float), np.nan)
                _mesh(ax_sim, v, w, sim_amp, AMP_NORM)
                fell = np.asarray(s["fell"], bool)
                vv, ww = np.meshgrid(v, w, indexing="ij")
                ax_sim.plot(vv[fell], ww[fell], "x", color="0.3", ms=3)
                with np.errstate(divide="ignore", invalid="ignore"):
                    rd = np.abs(sim_amp - orbit_amp) / orbit_amp * 100.0
                rd_mesh = _mesh(ax_rd, v, w, rd, RD_NORM, cmap="magma")
            else:
                for ax in (ax_sim, ax_rd):
                    ax.text(0.5, 0.5, "no simulation", transform=ax.transAxes, ha="center")
            for ax, name in zip((ax_ps, ax_orbit, ax_sim, ax_rd), panels, strict=True):
                ax.set_title(f"{model} {method} {coord}: {name}", fontsize=8)
        rows = a * len(panels)
        fig.colorbar(amp_mesh, ax=axes[rows:rows + 3, :], label="amplitude (rad)", shrink=0.9)
        if rd_mesh is not None:
            fig.colorbar(rd_mesh, ax=axes[rows + 3, :], label="RD (%)", shrink=0.9)
    _axes_labels(axes)
    return fig


def periodic_fine_maps(fine: Mapping[str, Mapping], method: str = "NT") -> plt.Figure:
    """Orbit amplitude maps of every model on the finer grid (one row per model, roll and
    steer); unstable orbits hatched."""
    models = list(fine)
    fig, axes = plt.subplots(len(models), 2, figsize=(7.0, 2.1 * len(models) + 0.8),
                             sharex=True, sharey=True, squeeze=False, layout="constrained")
    mesh = None
    for i, model in enumerate(models):
        d = fine[model]
        v, w = np.asarray(d["speed_m_s"]), np.asarray(d["omega_rad_s"])
        for j, coord in enumerate(("roll", "steer")):
            mesh = _mesh(axes[i, j], v, w, np.asarray(d[f"{coord}_amp_rad"], float), AMP_NORM)
            _unstable(axes[i, j], v, w, d["stable"], d["converged"])
            axes[i, j].set_title(f"{model} {method} {coord}", fontsize=9)
    _axes_labels(axes)
    fig.colorbar(mesh, ax=axes, label="cadence amplitude of the orbit (rad)", shrink=0.6)
    return fig


def periodic_continuation(branches: Mapping[str, Mapping]) -> plt.Figure:
    """Continuation diagram at the reference cadence, one row per model: roll amplitude (left)
    and the largest Floquet multiplier modulus (right) along each branch (solid: stable, dashed:
    unstable, markers: multiplier crossings), the linear-limit branch scaled back to full torque
    (dotted), and the self-stable speeds of the model's own linearisation (shaded)."""
    models = list(branches)
    fig, axes = plt.subplots(len(models), 2, figsize=(7.0, 2.0 * len(models) + 0.6),
                             sharex=True, squeeze=False, layout="constrained")
    colors = {"NT": "C0", "NP": "C1"}
    for j, model in enumerate(models):
        b = branches[model]
        ax_amp, ax_mu = axes[j, 0], axes[j, 1]
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
                for ax, y in ((ax_amp, amp), (ax_mu, mu)):
                    ax.plot(v, np.where(st, y, np.nan), style, color=colors.get(method, "k"),
                            label=label if ax is ax_amp else None)
                    ax.plot(v, np.where(st, np.nan, y), "--" if scale == 1 else ":",
                            color=colors.get(method, "k"), alpha=0.6)
                for c in np.asarray(b[f"{key}crossing_values"]):
                    ax_mu.plot(c, 1.0, "o", mfc="none", color=colors.get(method, "k"))
        for lo, hi in np.asarray(b["linear_stable_ranges_m_s"]).reshape(-1, 2):
            for ax in axes[j, :]:
                ax.axvspan(lo, hi, color="0.85", lw=0, zorder=0)
        ax_amp.set_title(f"{model}, {float(b['cadence_rpm']):g} rpm", fontsize=9)
        ax_amp.set_yscale("log")
        ax_mu.set_yscale("log")
        ax_mu.axhline(1.0, color="k", lw=0.6)
        ax_amp.set_ylabel("roll amplitude (rad)")
        ax_mu.set_ylabel("max |Floquet multiplier|")
    for ax in axes[-1, :]:
        ax.set_xlabel("forward speed v (m/s)")
    axes[0, 0].legend(fontsize=8)
    return fig
