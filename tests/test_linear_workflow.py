"""The linear part's outputs of the quick-profile workflow (shared session run, conftest.py)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from pedalrepro import report
from pedalrepro.figures import registry

pytestmark = pytest.mark.workflow

TIME_KEYS = ("speed_m_s", "omega_rad_s", "roll_amp_rad", "steer_amp_rad", "t_end_s", "fell",
             "example_speed_m_s", "example_omega_rad_s", "example_t_s", "example_roll_rad",
             "example_steer_rad")


@pytest.fixture(scope="module")
def results(quick_workflow):
    if quick_workflow.returncode != 0:
        pytest.fail("the quick workflow failed (see tests/test_workflow.py)")
    return quick_workflow.results


def test_eigen_summary(results, published):
    df = pd.read_csv(results / "tables" / "eigen_summary.csv").set_index("model")
    assert list(df.columns[:5]) == ["weave_speed_m_s", "capsize_speed_m_s", "stable_from_m_s",
                                    "stable_to_m_s", "weave_frequency_at_weave_speed_rad_s"]
    assert list(df.index) == ["benchmark", "HS", "CF", "HR", "CR"]
    assert df.loc["benchmark", "weave_speed_m_s"] == pytest.approx(4.2924, abs=1e-3)
    assert np.isnan(df.loc["CF", "stable_from_m_s"]) and np.isnan(df.loc["CF", "capsize_speed_m_s"])
    assert df.loc["CF", "weave_speed_m_s"] == pytest.approx(3.21, abs=0.01)


def test_table_4_1_model_csv(results, published):
    df = pd.read_csv(results / "tables" / "table_4_1_model.csv")
    assert list(df.columns) == ["system", "speed_kmh", "cadence_rpm", "roll_model_rad",
                                "steer_model_rad"]
    pub = published["table_4_1_model_validation"]
    assert df["system"].tolist() == pub["system"]
    np.testing.assert_allclose(df["speed_kmh"], pub["speed_kmh"])
    np.testing.assert_allclose(df["roll_model_rad"], pub["roll_model_rad"], atol=5e-4 + 1e-12)
    np.testing.assert_allclose(df["steer_model_rad"], pub["steer_model_rad"], atol=5e-4 + 1.1e-5)


def test_time_npz_format_and_figures(results):
    for method in ("LA", "LN"):
        for model in ("HS", "CF", "HR", "CR"):
            with np.load(results / "intermediate" / "time" / f"{method}_{model}.npz") as d:
                assert set(TIME_KEYS) <= set(d.files)
                n_v, n_w = len(d["speed_m_s"]), len(d["omega_rad_s"])
                assert d["roll_amp_rad"].shape == d["fell"].shape == (n_v, n_w)
                assert d["example_roll_rad"].shape == (6, len(d["example_t_s"]))
                assert np.all(np.isfinite(d["roll_amp_rad"]))  # never a silent NaN table
    for fid in registry.ids(part="linear"):
        for fmt in ("png", "pdf"):
            assert (results / "figures" / f"{fid}.{fmt}").stat().st_size > 10_000, fid


def test_linear_report_part(results):
    df = pd.read_csv(results / "tables" / "report" / "linear.csv", dtype=str,
                     keep_default_na=False)
    assert list(df.columns) == list(report.COLUMNS)
    assert set(df["status"]) <= set(report.STATUSES)
    # one row per claim id of the linear part (claims.yaml), with the grid's own values
    rows = report.by_id(df, "benchmark.", "self_stable_range_exists", "cf_weave_stable_speed",
                        "hs_weave_frequency", "benchmark_ps_maximum.", "normal_cycling_amplitude.",
                        "gear_ratio_amplitude_max.", "rd_1c.", "rd_2b.", "rd_3a.", "rd_3b.",
                        "rd_4a.", "rd_5_hr_hs.", "rd_5_cr_cf.", "rd_6_cr_hr.", "table_4_1.model.")
    assert len(rows) == len(df)
    weave = report.by_id(df, "benchmark.weave_speed").iloc[0]
    # Meijaard et al. 2007: 4.292382785 m/s; the row prints 6 significant digits (1e-5 m/s)
    assert float(weave["reproduced"]) == pytest.approx(4.292383, abs=1e-5)
    assert weave["status"] == "reproduced"
