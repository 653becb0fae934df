"""Section 2 figure functions: each draws the arrays it is given (pedalrepro.figures.section2)."""

from __future__ import annotations

import matplotlib
import matplotlib.image

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from pedalrepro import disturbance, figures, legs  # noqa: E402
from pedalrepro.figures import section2  # noqa: E402

IDS = ("fig_2_2", "fig_2_3", "fig_2_4", "fig_2_5", "fig_2_6", "fig_2_7", "fig_d_1")


@pytest.fixture(scope="module")
def data():
    d = disturbance.pedalling_disturbance("hybrid", samples_per_revolution=360)
    return disturbance.to_arrays(d)


def _ydata(ax):
    return [np.asarray(line.get_ydata(), float) for line in ax.get_lines()]


def _expected_curves(fid, data):
    """(axes index, the y-data each of its first curves must show) per figure, from the arrays
    the figure is given: the data drawn, not only that a figure came back."""
    closed = lambda a: np.concatenate([a, a[:1]])  # noqa: E731  (paths are drawn closed)
    n, w = np.asarray(data["spectrum_n"]), float(data["cadence_rad_s"])
    amp = np.asarray(data["spectrum_com_amplitude_m"])
    sel = n >= 1
    return {
        # side view: leg-model and cadence-only COM paths (z column against x)
        "fig_2_2": [(1, [closed(data["com_m"])[:, 1], closed(data["com_simple_m"])[:, 1]])],
        # acceleration panel: |X(n w)| (n w)^2, forward then vertical
        "fig_2_4": [(2, [(amp[:, 0] * (n * w) ** 2)[sel], (amp[:, 1] * (n * w) ** 2)[sel]])],
        "fig_2_5": [(0, [data["force_n"][:, 0], data["force_simple_n"][:, 0]]),
                    (1, [data["force_n"][:, 2], data["force_simple_n"][:, 2]])],
        "fig_2_6": [(k, [data["torque_nm"][:, k], data["torque_simple_nm"][:, k]])
                    for k in range(3)],
        "fig_2_7": [(k, [data["generalised_nm"][:, k], data["generalised_simple_nm"][:, k]])
                    for k in range(2)],
        "fig_2_3": [(0, [data["com_m"][:, 0], data["com_simple_m"][:, 0]])],
        "fig_d_1": [(1, [data[f"pitch_rate_{s}_rad_s"] for s in ("crank", "shank", "thigh")])],
    }[fid]


@pytest.mark.parametrize("fid", IDS)
def test_every_figure_draws_its_data_and_saves_it(fid, data, tmp_path):
    with figures.style():
        fig = getattr(section2, fid)(data)
        width_in = float(fig.get_size_inches()[0])
        save_dpi = float(matplotlib.rcParams["savefig.dpi"])
    for ax_index, curves in _expected_curves(fid, data):
        drawn = _ydata(fig.axes[ax_index])
        assert len(drawn) >= len(curves), (fid, ax_index)
        for got, want in zip(drawn, curves, strict=False):
            np.testing.assert_allclose(got, np.asarray(want, float), rtol=1e-12, atol=0)
    out = figures.save(fig, tmp_path / f"{fid}.png")
    # the PNG written is the figure at the style's savefig resolution; the tight bounding box
    # trims or pads at most a few per cent of the width (figures are drawn at 7 in for the page)
    width = matplotlib.image.imread(out).shape[1]
    assert abs(width - width_in * save_dpi) <= 0.05 * width_in * save_dpi, (fid, width)


def test_fig_2_3_draws_the_com_signals(data):
    with figures.style():
        fig = section2.fig_2_3(data)
    ax = fig.axes[4]  # acceleration, forward
    four_bar, simple = ax.get_lines()[:2]
    np.testing.assert_array_equal(four_bar.get_ydata(), data["com_acc_m_s2"][:, 0])
    np.testing.assert_array_equal(simple.get_ydata(), data["com_simple_acc_m_s2"][:, 0])
    np.testing.assert_allclose(four_bar.get_xdata(), np.rad2deg(data["crank_angle_rad"]))
    assert fig.axes[1].yaxis_inverted() and not fig.axes[0].yaxis_inverted()  # z down


def test_fig_2_7_draws_generalised_torques(data):
    with figures.style():
        fig = section2.fig_2_7(data)
    roll, simple = fig.axes[0].get_lines()[:2]
    np.testing.assert_array_equal(roll.get_ydata(), data["generalised_nm"][:, 0])
    np.testing.assert_array_equal(simple.get_ydata(), data["generalised_simple_nm"][:, 0])


def test_spectrum_arrays_match_table_d_1(data):
    x, z = legs.com_fourier(legs.leg_geometry("hybrid", "O"), (1, 2, 3))
    amp = data["spectrum_com_amplitude_m"]
    np.testing.assert_allclose(amp[1:4, 0], np.abs(x), rtol=1e-10)
    np.testing.assert_allclose(amp[1:4, 1], np.abs(z), rtol=1e-10)


def test_table_d_1_wide_layout():
    rows = [{"case": c, "axis": a, "n": n, "amplitude_m": 1.0 + n, "phase_rad": -n}
            for c in ("hybrid_O", "city_W") for a in ("X", "Z") for n in (1, 2)]
    wide = section2.table_d_1_wide(pd.DataFrame(rows))
    assert list(wide.columns) == ["quantity", "n", "hybrid_O", "city_W"]
    assert len(wide) == 8 and wide["hybrid_O"].iloc[0] == 2.0
