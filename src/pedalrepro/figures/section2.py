"""Figures of thesis Section 2 (the pedalling disturbance) and Appendix D.

Each function takes the arrays written by the ``section2_disturbance`` rule
(``results/intermediate/section2/disturbance_<bicycle>.npz``, keys documented in
:func:`pedalrepro.disturbance.to_arrays`; any mapping of name -> array works, e.g. ``np.load``)
or the Table D.1 DataFrame, and returns a matplotlib ``Figure``. Draw inside
``with figures.style():``. Crank angle on the x axes is ``omega t = -theta_A`` in degrees, 0 with
the right foot forward; ``z`` points down, so vertical axes are inverted as in the thesis.
"""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

__all__ = [
    "SEGMENTS", "SEGMENT_COLOURS", "LEG", "SIMPLE", "fig_2_2", "fig_2_3", "fig_2_4", "fig_2_5",
    "fig_2_6", "fig_2_7", "fig_d_1", "table_d_1_wide", "deviation_from_table_d_1",
]

SEGMENTS = ("crank", "shank", "thigh")
SEGMENT_COLOURS = {"crank": "tab:green", "shank": "tab:orange", "thigh": "tab:purple"}
LEG = "leg model (four-bar)"
SIMPLE = "cadence only (Eq 2.4)"


def _deg(data: Mapping[str, np.ndarray]) -> np.ndarray:
    return np.rad2deg(np.asarray(data["crank_angle_rad"]))


def _crank_axis(ax) -> None:
    ax.set_xlim(0, 360)
    ax.set_xticks(np.arange(0, 361, 90))


def _closed(a: np.ndarray) -> np.ndarray:
    """Repeat the first sample at the end so a periodic path plots closed."""
    return np.concatenate([a, a[:1]], axis=0)


def fig_2_2(data: Mapping[str, np.ndarray], snapshots: int = 4) -> Figure:
    """Fig 2.2: leg COM paths of both legs in 3D, side and front views; four-bar vs cadence-only
    skew-elliptical path, with the segment COM paths and a few four-bar positions (right leg)."""
    half = float(data["hip_width_m"]) / 2.0
    fig = plt.figure(figsize=(7.0, 8.0), layout="constrained")
    gs = fig.add_gridspec(2, 2, height_ratios=[1.0, 1.25])
    ax3 = fig.add_subplot(gs[0, 0], projection="3d")
    front = fig.add_subplot(gs[0, 1])
    side = fig.add_subplot(gs[1, :])
    for prefix, y, ls in (("", half, "-"), ("left_", -half, "--")):
        com = _closed(np.asarray(data[f"{prefix}com_m"]))
        simple = _closed(np.asarray(data[f"{prefix}com_simple_m"]))
        lab = "right" if not prefix else "left"
        ax3.plot(com[:, 0], np.full(len(com), y), com[:, 1], "C0" + ls, label=f"leg COM {lab}")
        ax3.plot(simple[:, 0], np.full(len(simple), y), simple[:, 1], "C1" + ls, lw=1)
        for s in SEGMENTS:
            seg = _closed(np.asarray(data[f"{prefix}segment_com_{s}_m"]))
            ax3.plot(seg[:, 0], np.full(len(seg), y), seg[:, 1], color=SEGMENT_COLOURS[s], lw=0.7,
                     ls=ls)
        front.plot(np.full(len(com), y), com[:, 1], "C0" + ls)
        front.plot(np.full(len(simple), y), simple[:, 1], "C1" + ls, lw=1)
    com = _closed(np.asarray(data["com_m"]))
    simple = _closed(np.asarray(data["com_simple_m"]))
    side.plot(com[:, 0], com[:, 1], "C0", label=f"leg COM, {LEG}")
    side.plot(simple[:, 0], simple[:, 1], "C1", lw=1, label=f"leg COM, {SIMPLE}")
    for s in SEGMENTS:
        seg = _closed(np.asarray(data[f"segment_com_{s}_m"]))
        side.plot(seg[:, 0], seg[:, 1], color=SEGMENT_COLOURS[s], lw=0.8, label=f"{s} COM")
    n = len(data["crank_angle_rad"])
    for i in (np.arange(snapshots) * n) // snapshots:
        chain = np.array([[0.0, 0.0], data["pedal_m"][i], data["knee_m"][i], data["hip_m"][i]])
        side.plot(chain[:, 0], chain[:, 1], "k-o", lw=0.6, ms=2, alpha=0.5)
    side.plot(0, 0, "ks", ms=4)
    side.annotate("crank axis A", (0, 0), (0.03, 0.12), fontsize=8)
    side.annotate("hip C", tuple(np.asarray(data["hip_m"])[0]), fontsize=8)
    side.set_aspect("equal")
    side.invert_yaxis()
    side.set_xlabel("x forward (m)")
    side.set_ylabel("z down (m)")
    side.set_title("side view (right leg, sagittal plane)")
    side.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    front.invert_yaxis()
    front.yaxis.tick_right()  # away from the 3D view's z label
    front.yaxis.set_label_position("right")
    front.set_xlabel("y right (m)")
    front.set_ylabel("z down (m)")
    front.set_title("front view (both legs)")
    front.set_xlim(-2 * half, 2 * half)
    ax3.invert_zaxis()
    ax3.set_xlabel("x (m)")
    ax3.set_ylabel("y (m)")
    ax3.set_zlabel("z (m)")
    ax3.set_title("3D view (both legs)")
    return fig


def fig_2_3(data: Mapping[str, np.ndarray]) -> Figure:
    """Fig 2.3: right-leg COM position, speed and acceleration vs crank angle, forward (left) and
    vertical (right, axis inverted), four-bar vs cadence-only."""
    deg = _deg(data)
    rows = (("com_m", "com_simple_m", "position (m)"),
            ("com_vel_m_s", "com_simple_vel_m_s", "speed (m/s)"),
            ("com_acc_m_s2", "com_simple_acc_m_s2", "acceleration (m/s$^2$)"))
    fig, axes = plt.subplots(3, 2, figsize=(7.0, 7.0), sharex=True, layout="constrained")
    for r, (key, skey, label) in enumerate(rows):
        for c, axis in enumerate(("forward x", "vertical z")):
            ax = axes[r, c]
            ax.plot(deg, np.asarray(data[key])[:, c], "C0", label=LEG)
            ax.plot(deg, np.asarray(data[skey])[:, c], "C1--", label=SIMPLE)
            ax.set_ylabel(f"{axis} {label}")
            if c == 1:
                ax.invert_yaxis()
            _crank_axis(ax)
    for ax in axes[-1]:
        ax.set_xlabel(r"crank angle $\omega t$ (deg)")
    axes[0, 0].legend()
    w = float(data["cadence_rad_s"])
    fig.suptitle(f"Right-leg COM at {w * 30 / np.pi:.0f} rpm")
    return fig


def fig_2_4(data: Mapping[str, np.ndarray], max_harmonic: int = 10) -> Figure:
    """Fig 2.4: amplitude spectrum of the right-leg COM position (and, to show the n and n^2
    growth, of its speed and acceleration) at multiples of the cadence."""
    n = np.asarray(data["spectrum_n"])
    amp = np.asarray(data["spectrum_com_amplitude_m"])
    w = float(data["cadence_rad_s"])
    f_hz = n * w / (2 * np.pi)
    fig, axes = plt.subplots(1, 3, figsize=(7.0, 3.4), layout="constrained")
    labels = ("position (m)", "speed (m/s)", "acceleration (m/s$^2$)")
    for k, ax in enumerate(axes):
        scale = (n * w) ** k
        for c, name in enumerate(("forward X", "vertical Z")):
            sel = n >= (1 if k else 0)
            off = (c - 0.5) * 0.08 * (f_hz[1] - f_hz[0])
            ax.vlines(f_hz[sel] + off, 0, (amp[:, c] * scale)[sel], color=f"C{c}", lw=2)
            ax.plot(f_hz[sel] + off, (amp[:, c] * scale)[sel], "o", color=f"C{c}", ms=3,
                    label=name)
        ax.set_yscale("log")
        top = np.max(amp[1:] * scale[1:, None])
        ax.set_ylim(top * 1e-6, top * 3)
        ax.set_xlim(-0.5 * f_hz[1], (max_harmonic + 0.5) * f_hz[1])
        ax.set_xlabel("frequency (Hz)")
        ax.set_title(labels[k])
    axes[0].set_ylabel("amplitude")
    axes[0].legend()
    fig.suptitle(f"Right-leg COM spectrum, cadence {w / (2 * np.pi):.3g} Hz")
    return fig


def fig_2_5(data: Mapping[str, np.ndarray]) -> Figure:
    """Fig 2.5: d'Alembert forces of both legs (Eq 2.8) vs crank angle, forward and vertical,
    four-bar vs cadence-only (whose forces cancel exactly)."""
    return _crank_panels(data, "force_n", ((0, "forward $F_x$"), (2, "vertical $F_z$")), "N",
                         7.0)


def _crank_panels(data: Mapping[str, np.ndarray], key: str, panels: tuple[tuple[int, str], ...],
                  unit: str, width_in: float) -> Figure:
    """One panel per ``(column, name)`` of ``panels``: ``data[key]`` (leg model) and its
    simplified counterpart (``force_n`` -> ``force_simple_n``) against the crank angle."""
    deg = _deg(data)
    fig, axes = plt.subplots(1, len(panels), figsize=(width_in, 3.4), sharex=True,
                             layout="constrained")
    quantity, suffix = key.rsplit("_", 1)
    for ax, (col, name) in zip(axes, panels, strict=True):
        ax.plot(deg, np.asarray(data[key])[:, col], "C0", label=LEG)
        ax.plot(deg, np.asarray(data[f"{quantity}_simple_{suffix}"])[:, col], "C1--",
                label=SIMPLE)
        ax.set_ylabel(f"{name} ({unit})")
        ax.set_xlabel(r"crank angle $\omega t$ (deg)")
        _crank_axis(ax)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=2)
    return fig


def fig_2_6(data: Mapping[str, np.ndarray]) -> Figure:
    """Fig 2.6: Cartesian d'Alembert torques (Eq 2.9) roll, pitch and yaw vs crank angle."""
    return _crank_panels(data, "torque_nm",
                         ((0, "roll $T_x$"), (1, "pitch $T_y$"), (2, "yaw $T_z$")), "N m", 7.0)


def fig_2_7(data: Mapping[str, np.ndarray]) -> Figure:
    """Fig 2.7: generalised roll and steer torques (Eq 2.15, 2.22, 2.24) vs crank angle."""
    return _crank_panels(data, "generalised_nm",
                         ((0, r"roll $T_\phi$"), (1, r"steer $T_\delta$")), "N m", 7.0)


def fig_d_1(data: Mapping[str, np.ndarray]) -> Figure:
    """Fig D.1: pitch angle, rate and acceleration of crank, lower leg and upper leg (right leg)."""
    deg = _deg(data)
    fig, axes = plt.subplots(3, 1, figsize=(6.5, 7.0), sharex=True, layout="constrained")
    keys = (("pitch_{}_rad", "pitch angle (deg)", True),
            ("pitch_rate_{}_rad_s", "pitch rate (rad/s)", False),
            ("pitch_acc_{}_rad_s2", "pitch acceleration (rad/s$^2$)", False))
    names = {"crank": "crank", "shank": "lower leg", "thigh": "upper leg"}
    for ax, (key, label, angle) in zip(axes, keys, strict=True):
        for k, s in enumerate(SEGMENTS):
            y = np.asarray(data[key.format(s)])
            if angle:
                y = np.rad2deg(np.unwrap(y))
            ax.plot(deg, y, color=f"C{k}", label=names[s])
        ax.set_ylabel(label)
        _crank_axis(ax)
    axes[0].legend()
    axes[-1].set_xlabel(r"crank angle $\omega t$ (deg)")
    return fig


def table_d_1_wide(table: pd.DataFrame) -> pd.DataFrame:
    """Table D.1 in the thesis's layout: rows ``|X(n w)|``, ``angle X``, ... columns = cases."""
    rows = []
    for axis in ("X", "Z"):
        for what, col in (("|{a}(n w)| (m)", "amplitude_m"), ("angle {a}(n w) (rad)", "phase_rad")):
            for n in sorted(table["n"].unique()):
                sel = table[(table["axis"] == axis) & (table["n"] == n)]
                rows.append({"quantity": what.format(a=axis), "n": int(n),
                             **dict(zip(sel["case"], sel[col], strict=True))})
    return pd.DataFrame(rows)


def deviation_from_table_d_1(table: pd.DataFrame, published: pd.DataFrame) -> Figure:
    """Relative amplitude deviation and phase deviation of Table D.1 from the published table
    (long format, same columns), per case and harmonic; a check figure, not in the thesis."""
    merged = table.merge(published, on=["case", "axis", "n"], suffixes=("", "_pub"))
    rel = np.abs(merged["amplitude_m"] / merged["amplitude_m_pub"] - 1)
    dphi = np.abs(np.angle(np.exp(1j * (merged["phase_rad"] - merged["phase_rad_pub"]))))
    fig, axes = plt.subplots(1, 2, figsize=(7.0, 3.0), layout="constrained")
    for ax, vals, name in ((axes[0], rel, "relative amplitude deviation"),
                           (axes[1], dphi, "phase deviation (rad)")):
        ax.semilogy(np.arange(len(vals)), np.maximum(vals, 1e-17), "o", ms=3)
        ax.axhline(1e-6, color="C3", ls="--", lw=1, label="1e-6 requirement")
        ax.set_xlabel("entry (case x axis x n)")
        ax.set_ylabel(name)
    axes[0].legend()
    return fig
