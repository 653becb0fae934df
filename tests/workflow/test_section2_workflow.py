"""The Section 2 rules end to end: the outputs of the shared quick-profile run (``quick_workflow``,
tests/conftest.py; ``config/quick.yaml``, the profile this file used to run on its own)."""

from __future__ import annotations

import matplotlib
import matplotlib.image
import numpy as np
import pandas as pd
import pytest

from pedalrepro import figures, report
from pedalrepro.figures import section2

pytestmark = pytest.mark.workflow

FIGURES = ("fig_2_2", "fig_2_3", "fig_2_4", "fig_2_5", "fig_2_6", "fig_2_7", "fig_d_1")


@pytest.fixture(scope="module")
def section2_run(quick_workflow):
    """The results folder of the shared quick-profile run (conftest.py): the book's inputs
    include every file read here (rules/section2.smk: Table D.1, the section-2 numbers, both
    bicycles' disturbance arrays, the report part; rules/figures.smk: every registry figure)."""
    if quick_workflow.returncode != 0:
        pytest.fail("the quick workflow failed (see tests/workflow/test_workflow.py)")
    return quick_workflow.results


def test_table_d_1_csv(section2_run, published):
    df = pd.read_csv(section2_run / "tables" / "table_d_1.csv")
    assert list(df.columns) == ["case", "axis", "n", "amplitude_m", "phase_rad"]
    assert len(df) == 4 * 2 * 5
    pub = published["table_D1_leg_com_fourier"]
    for (case, axis), grp in df.groupby(["case", "axis"]):
        grp = grp.sort_values("n")
        np.testing.assert_allclose(grp["amplitude_m"], pub[case][f"amplitude_{axis}"], rtol=1e-6)
        np.testing.assert_allclose(grp["phase_rad"], pub[case][f"phase_{axis}"], atol=1e-6)


def test_section2_report_rows(section2_run):
    df = pd.read_csv(section2_run / "tables" / "report" / "section2.csv", dtype=str,
                     keep_default_na=False)
    assert list(df.columns) == list(report.COLUMNS)
    d1 = report.by_id(df, "table_d_1.")
    assert len(d1) == 80 and set(d1["status"]) == {report.REPRODUCED}
    # every Section 2 claim of claims.yaml has a row
    claims = report.by_id(df, "nrmsd_com_x", "nrmsd_com_z", "nrmsd_roll_torque",
                          "nrmsd_steer_torque", "dalembert_force_x.", "dalembert_force_z.",
                          "winter_vs_homogeneous.", "force_torque_harmonics",
                          "nrmsd_cadence_dependence", "city_seat_reach")
    assert len(claims) + len(d1) == len(df)
    # Sec 2.2.1: 3.6 % vertical COM NRMSD, printed with one decimal
    assert float(report.by_id(df, "nrmsd_com_z")["reproduced"].iloc[0]) == pytest.approx(3.6,
                                                                                       abs=0.05)
    # differences carry an explanation
    assert (claims.loc[claims["status"] == report.DIFFERS, "note"].str.len() > 20).all()


def test_section2_outputs_hold_the_data(section2_run, published, tmp_path):
    with np.load(section2_run / "intermediate" / "section2" / "disturbance_city.npz") as npz:
        com = npz["com_m"]
        assert com.shape == (720, 2)  # quick profile: 720 samples per revolution
        assert float(npz["cadence_rad_s"]) == pytest.approx(2 * np.pi, rel=1e-12)  # 60 rpm
    # The DFT of the written COM path is Table D.1 (city, homogeneous legs): 720 samples per
    # revolution resolve the published 14-digit amplitudes of n = 1..5 to rel 1e-6.
    amp = np.abs(np.fft.rfft(com, axis=0)[1:6]) * 2 / len(com)
    pub = published["table_D1_leg_com_fourier"]["city_O"]
    np.testing.assert_allclose(amp[:, 0], pub["amplitude_X"], rtol=1e-6)
    np.testing.assert_allclose(amp[:, 1], pub["amplitude_Z"], rtol=1e-6)
    # Every figure written is the drawing of the arrays written: redrawn here from the rule's
    # input file, pixel for pixel.
    with np.load(section2_run / "intermediate" / "section2" / "disturbance_hybrid.npz") as npz:
        data = dict(npz)
    for f in FIGURES:
        with figures.style():  # drawn in the style, saved after it, as the rule does
            fig = getattr(section2, f)(data)
        redrawn = figures.save(fig, tmp_path / f"{f}.png")
        written = matplotlib.image.imread(section2_run / "figures" / f"{f}.png")
        np.testing.assert_array_equal(written, matplotlib.image.imread(redrawn), err_msg=f)
