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
        pytest.fail("the quick workflow failed (see tests/workflow/test_workflow.py)")
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


def test_rd_4_median_recomputed_by_a_separate_path(results):
    """Evaluation point 4 (Sec 3.2.5, claim rd_4a): the median RD of HR's cadence amplitudes
    against the 60 rpm / 5 m/s reference over the normal-cycling ellipse, recomputed here from the
    Appendix B matrices (read from the YAML file) with one ``numpy.linalg.solve`` per grid point
    and harmonic and an ellipse test written out again, not by calling the pipeline's batched
    Cramer solve, its RD maps or its mask. Agreement to the 6 significant digits of
    rd_summary.csv."""
    import yaml

    from pedalrepro import paths, response

    mats = yaml.safe_load((paths.PARAMETERS / "appendix_b.yaml").read_text())[
        "appendix_B_linear_models"]["HR"]
    m_, c1, k0, k2 = (np.array(mats[k], float) for k in ("M", "C1", "K0", "K2"))
    h = response.forcing("HR", (1, 3, 5))  # the pedalling torque: an input of both paths
    n = np.asarray(h.n)
    coef = np.stack([np.asarray(h.roll), np.asarray(h.steer)], axis=-1)  # (k, 2), Eq 3.14

    def roll_amplitude(v: float, w: float) -> float:
        f = w  # the cadence harmonic n = 1
        a = -(f**2) * m_ + 1j * f * v * c1 + 9.81 * k0 + v**2 * k2
        return float(abs(np.linalg.solve(a, coef[int(np.nonzero(n == 1)[0][0])] * f**2)[0]))

    ps = np.load(results / "intermediate" / "ps" / "HR.npz")
    v, w = ps["speed_m_s"], ps["omega_rad_s"]
    ref = roll_amplitude(5.0, 60 * np.pi / 30)
    v0, v1 = 14.0 / 3.6, 22.0 / 3.6  # config linear.normal_cycling_speed_kmh
    w0, w1 = 50 * np.pi / 30, 80 * np.pi / 30  # config linear.normal_cycling_cadence_rpm
    rds = [abs((ref - roll_amplitude(vi, wj)) / ref) * 100
           for vi in v for wj in w
           if ((vi - (v0 + v1) / 2) / ((v1 - v0) / 2)) ** 2
           + ((wj - (w0 + w1) / 2) / ((w1 - w0) / 2)) ** 2 <= 1 and wj > 0]
    assert len(rds) >= 10
    rd = pd.read_csv(results / "tables" / "rd_summary.csv")
    row = rd[(rd.model == "HR") & (rd.point == "4") & (rd.coordinate == "roll")
             & (rd.region == "normal cycling")].iloc[0]
    assert int(row["count"]) == len(rds)
    assert float(row["median_percent"]) == pytest.approx(float(np.median(rds)), rel=1e-5)
