"""Figures of the non-linear models (thesis Sec 3.1.1.3, 3.2.4): fig_3_34 and the model checks."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.colors import LogNorm


def fig_3_34(maps: Mapping[str, np.ndarray]) -> plt.Figure:
    """RD (Eq 3.26) of the particular solution vs the non-linear pedalling model NP (Fig 3.34).

    Parameters
    ----------
    maps
        ``speed_m_s``, ``omega_rad_s``, ``models`` and ``<model>_<roll|steer>_ps_np`` (percent,
        speed x cadence), ``<model>_stable`` (speeds inside the self-stable range), as written by
        the ``nonlinear_report`` rule (``results/intermediate/nonlinear/rd_maps.npz``).
    """
    v, w = np.asarray(maps["speed_m_s"]), np.asarray(maps["omega_rad_s"])
    models = [str(m) for m in np.atleast_1d(maps["models"])]
    fig, axes = plt.subplots(2, len(models), figsize=(4.2 * len(models), 6.4), squeeze=False,
                             sharex=True, sharey=True)
    norm = LogNorm(1e-2, 1e2)
    mesh = None
    for j, name in enumerate(models):
        for i, dof in enumerate(("roll", "steer")):
            ax = axes[i, j]
            rd = np.asarray(maps[f"{name}_{dof}_ps_np"], float)
            shown = np.clip(np.where(np.isfinite(rd), rd, np.nan), 1e-2, 1e2)
            mesh = ax.pcolormesh(w, v, shown, norm=norm, cmap="viridis", shading="nearest")
            stable = np.asarray(maps[f"{name}_stable"], bool)
            if stable.any():
                half = 0.5 * (v[1] - v[0]) if v.size > 1 else 0.1
                ax.axhspan(v[stable].min() - half, v[stable].max() + half, fill=False, ls="--",
                           ec="w", lw=1.2)
            ax.set_title(f"{name}: {dof}")
            if i == 1:
                ax.set_xlabel(r"cadence $\omega$ (rad/s)")
            if j == 0:
                ax.set_ylabel("speed v (m/s)")
    fig.colorbar(mesh, ax=axes, label="RD PS vs NP (%)")
    return fig


def fig_linearisation_vs_appendix_b(table: pd.DataFrame) -> plt.Figure:
    """Relative difference of the project's linearisations from thesis Appendix B.

    ``table``: ``linearisation_vs_appendix_b.csv``. HR, CR, CF (arm loops): the models' own
    linearisation; HS: the rigid-rider body of the substitute before its correction
    (``compared`` column).
    """
    fig, ax = plt.subplots(figsize=(7, 3.2))
    labels = [f"{r.matrix}[{r.i}{r.j}]" for r in table.itertuples()]
    for name, group in table.groupby("model", sort=False):
        idx = [k for k, r in enumerate(table.itertuples()) if r.model == name]
        ax.plot(idx, 100 * group["rel_diff"].to_numpy(), "o", label=name)
    ax.set_xticks(range(len(labels)), labels, rotation=90, fontsize=7)
    ax.set_ylabel("|project - App. B| / |App. B| (%)")
    ax.legend(fontsize=7, ncols=2)
    return fig


def fig_e_1(cf: Mapping[str, np.ndarray], cf_original_seat: Mapping[str, np.ndarray]
            ) -> plt.Figure:
    """Fig E.1: CF eigenvalues with the original 0.77 m seat post beside the 0.72 m one.

    Parameters
    ----------
    cf
        Eigen sweep of the project's own CF with its arm loops, seat 0.72 m
        (``results/intermediate/nonlinear/eigen_cf_own.npz``).
    cf_original_seat
        Eigen sweep of :func:`pedalrepro.nonlinear.models.original_seat_model`
        (``results/intermediate/nonlinear/eigen_cf_original_seat.npz``): the same model with the
        rider (shoulders included) not lowered, the hands on the handlebar.
    """
    from .linear import eigen_panel

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), sharey=True)
    eigen_panel(axes[0], cf, "CF (own model, arm loops), seat 0.72 m")
    eigen_panel(axes[1], cf_original_seat, "CF (own model, arm loops), seat 0.77 m")
    axes[0].legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    return fig


def example_runs(nt: Mapping[str, np.ndarray], np_: Mapping[str, np.ndarray],
                 model: str = "") -> plt.Figure:
    """Roll angle of the six example runs: NT (legs fixed + torques) against NP (moving legs).

    ``nt``, ``np_``: the ``results/intermediate/time/<method>_<model>.npz`` contents.
    """
    t = np.asarray(nt["example_t_s"])
    fig, axes = plt.subplots(3, 2, figsize=(9, 6.5), sharex=True)
    for k, ax in enumerate(axes.T.ravel()):
        ax.plot(t, np.degrees(nt["example_roll_rad"][k]), lw=0.9, label="NT")
        ax.plot(t, np.degrees(np_["example_roll_rad"][k]), lw=0.9, ls="--", label="NP")
        ax.set_title(f"{model} point {k + 1}: v = {nt['example_speed_m_s'][k]:.1f} m/s, "
                     rf"$\omega$ = {nt['example_omega_rad_s'][k]:.1f} rad/s", fontsize=8)
        ax.set_ylabel("roll (deg)")
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes[0, 0].legend()
    return fig
