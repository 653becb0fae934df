"""Figures of the non-linear models (thesis Sec 3.1.1.3, 3.2.4): fig_3_34 and the model checks."""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from .palette import model_colour

__all__ = ["fig_3_34", "nonlinear_linearisation_vs_appendix_b", "fig_e_1", "figs_example_runs"]


def fig_3_34(maps: Mapping[str, np.ndarray],
             eigen: Mapping[str, Mapping[str, np.ndarray]] | None = None) -> plt.Figure:
    """RD (Eq 3.26) of the particular solution vs the non-linear pedalling model NP (Fig 3.34).

    As every other map: forward speed on x, cadence on y; one row per model, roll (left) and
    steer (right); the colour bar labels the thesis's levels (0.1, 1, 2.5, 5, 10, 25, 100 %);
    the self-stable speeds between two vertical lines (colours unchanged) and the weave
    imaginary part dashed (Appendix B linear model's, ``eigen``), as the thesis's caption.

    Parameters
    ----------
    maps
        ``speed_m_s``, ``omega_rad_s``, ``models`` and ``<model>_<roll|steer>_ps_np`` (percent,
        speed x cadence), ``<model>_stable`` (speeds inside the self-stable range), as written by
        the ``nonlinear_rd`` rule (``results/intermediate/nonlinear/rd_maps.npz``).
    eigen
        Optional eigen sweeps by model (``results/intermediate/eigen/<model>.npz``) for the
        weave line.
    """
    from .linear import WIDTH_IN, rd_colorbar, rd_map

    v, w = np.asarray(maps["speed_m_s"]), np.asarray(maps["omega_rad_s"])
    models = [str(m) for m in np.atleast_1d(maps["models"])]
    fig, axes = plt.subplots(len(models), 2, figsize=(WIDTH_IN, 0.8 + 2.1 * len(models)),
                             squeeze=False, sharex=True, sharey=True, layout="constrained")
    cs = None
    for i, name in enumerate(models):
        for j, dof in enumerate(("roll", "steer")):
            ax = axes[i, j]
            rd = np.asarray(maps[f"{name}_{dof}_ps_np"], float)
            cs = rd_map(ax, v, w, rd, None, f"{name}: {dof}, PS to NP")
            stable = np.asarray(maps[f"{name}_stable"], bool)
            if stable.any():
                half = 0.5 * (v[1] - v[0]) if v.size > 1 else 0.1
                for x in (v[stable].min() - half, v[stable].max() + half):
                    ax.axvline(x, color="w", lw=1.0)
            e = (eigen or {}).get(name)
            if e is not None:
                f = np.where(e["weave_frequency_rad_s"] > 0, e["weave_frequency_rad_s"], np.nan)
                ax.plot(e["speed_m_s"], f, color="w", ls="--", lw=1.0)
            ax.set_xlim(v.min(), v.max())
            ax.set_ylim(w.min(), w.max())
            if i == len(models) - 1:
                ax.set_xlabel("forward speed v (m/s)")
            if j == 0:
                ax.set_ylabel(r"cadence $\omega$ (rad/s)")
    rd_colorbar(fig, cs, axes, "RD PS vs NP (%)")
    return fig


def nonlinear_linearisation_vs_appendix_b(table: pd.DataFrame) -> plt.Figure:
    """Relative difference of the project's linearisations from thesis Appendix B.

    ``table``: ``linearisation_vs_appendix_b.csv``: the models' own linearisations (HS and CF
    with their arm loops).
    """
    fig, ax = plt.subplots(figsize=(7, 3.4), layout="constrained")
    labels = [f"{r.matrix}[{r.i}{r.j}]" for r in table.itertuples()]
    for name, group in table.groupby("model", sort=False):
        idx = [k for k, r in enumerate(table.itertuples()) if r.model == name]
        ax.plot(idx, 100 * group["rel_diff"].to_numpy(), "o", label=name,
                color=model_colour(str(name)))
    ax.set_xticks(range(len(labels)), labels, rotation=90, fontsize=8)
    ax.set_ylabel("|project - App. B| / |App. B| (%)")
    ax.legend(fontsize=8, ncols=2)
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
    from .linear import WIDTH_IN, eigen_panel

    fig, axes = plt.subplots(1, 2, figsize=(WIDTH_IN, 3.8), sharey=True, layout="constrained")
    eigen_panel(axes[0], cf, "CF, seat 0.72 m")
    eigen_panel(axes[1], cf_original_seat, "CF, seat 0.77 m")
    axes[0].legend(loc="lower left", fontsize=8)
    return fig


def figs_example_runs(nt: Mapping[str, np.ndarray], np_: Mapping[str, np.ndarray],
                 model: str = "") -> plt.Figure:
    """Roll angle of the six example runs: NT (legs fixed + torques) against NP (moving legs),
    one model each: ``nonlinear_examples_HS``, ``nonlinear_examples_CF``,
    ``nonlinear_examples_HR``, ``nonlinear_examples_CR`` (not thesis figures).

    ``nt``, ``np_``: the ``results/intermediate/time/<method>_<model>.npz`` contents.
    """
    t = np.asarray(nt["example_t_s"])
    from .palette import METHOD_STYLE

    fig, axes = plt.subplots(3, 2, figsize=(7, 6.5), sharex=True, layout="constrained")
    for k, ax in enumerate(axes.T.ravel()):
        ax.plot(t, np.degrees(nt["example_roll_rad"][k]), **METHOD_STYLE["NT"], label="NT")
        ax.plot(t, np.degrees(np_["example_roll_rad"][k]), **METHOD_STYLE["NP"], label="NP")
        ax.set_title(f"{model} {k + 1}: v = {nt['example_speed_m_s'][k]:.1f} m/s, "
                     rf"$\omega$ = {nt['example_omega_rad_s'][k]:.1f} rad/s", fontsize=8)
        ax.set_ylabel("roll (deg)")
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    axes[0, 0].legend()
    return fig
