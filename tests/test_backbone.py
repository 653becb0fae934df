"""Parameters, configuration schema and report plumbing."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pedalrepro import config, params, paths, report


def test_stratos_steer_geometry_from_raw_measurements():
    # Independent hand calculation from StratosMeasured.txt: rF = dF / (2 pi nF),
    # lam = 90 - 73.1 deg, c = (rF sin lam - f) / cos lam.
    r_f = 27.772 / (2 * math.pi * 13)
    lam = math.radians(16.9)
    c = (r_f * math.sin(lam) - 0.045) / math.cos(lam)
    g = params.stratos_geometry()
    assert g["rF"] == pytest.approx(r_f, rel=1e-12)
    assert g["lam"] == pytest.approx(lam, rel=1e-12)
    assert g["c"] == pytest.approx(c, rel=1e-12)


def test_browser_and_benchmark_parameters():
    b = params.benchmark_parameters("browser")
    assert b["w"] == 1.121 and b["c"] == pytest.approx(0.0685808540382)
    m = params.benchmark_parameters("benchmark")
    assert m["lam"] == pytest.approx(math.pi / 10, rel=1e-15)


def test_appendix_b_mass_matrices_symmetric_positive_definite():
    # Physics: a mass matrix is symmetric and positive definite.
    for name in params.MODELS:
        model = params.appendix_b_model(name)
        assert np.allclose(model.M, model.M.T, rtol=1e-14)
        assert np.all(np.linalg.eigvalsh(model.M) > 0)
    with pytest.raises(KeyError, match="unknown Appendix B model"):
        params.appendix_b_model("XX")


def test_one_model_list():
    """The model list is params.MODELS / params.LINEAR_MODELS (issue 26, part 4); the two copies
    kept free of the parameter files (the figure registry, the validation figures) equal it, and
    every thesis model has an Appendix B model and a non-linear model."""
    from pedalrepro import linear
    from pedalrepro.figures import registry
    from pedalrepro.figures import validation as fval
    from pedalrepro.nonlinear import settings

    assert params.LINEAR_MODELS == ("benchmark", *params.MODELS)
    assert registry.MODELS4 == fval.SYSTEMS == params.MODELS
    assert linear.MODEL_NAMES == settings.NONLINEAR_MODELS == params.LINEAR_MODELS
    assert set(params.MODELS) == set(params.BICYCLE_OF_MODEL)
    assert set(params.MODELS) <= set(settings.settings()["models"])


def test_leg_mass_is_sum_of_segments():
    legs = params.legs()
    m = legs["crank_mass_kg"] + legs["shank_mass_kg"] + legs["thigh_mass_kg"]
    assert m == pytest.approx(11.792, abs=1e-12)


def test_both_config_profiles_validate():
    full = config.load()
    quick = config.load(None, paths.CONFIG / "quick.yaml")
    assert full["profile"] == "thesis" and quick["profile"] == "quick"
    # the thesis grids: 10302 particular-solution points (Sec 3.1.2.2.1)
    lin = full["linear"]
    n_w = int(np.floor(lin["ps_omega_max_rad_s"] / lin["ps_omega_step_rad_s"] + 1e-9)) + 1
    n_v = int(round(lin["ps_speed_max_m_s"] / lin["ps_speed_step_m_s"])) + 1
    assert n_w * n_v == 10302


@pytest.mark.parametrize(
    "key, value, message",
    [
        (("seed",), -1, "minimum"),
        (("linear", "rtol"), 0.5, "maximum"),
        (("section2", "cadence_rpm"), "sixty", "not of type"),
        (("profile",), "huge", "is not one of"),
    ],
)
def test_config_outside_schema_is_a_clear_error(key, value, message):
    cfg = config.load()
    target = cfg
    for k in key[:-1]:
        target = target[k]
    target[key[-1]] = value
    with pytest.raises(config.ConfigError, match=message) as info:
        config.validate(cfg)
    assert ".".join(key) in str(info.value)


def test_report_check_and_nan_rejected(tmp_path):
    # Sec 2.2.1 vertical COM NRMSD 3.6 %, one decimal: abs 0.05 (data/published/claims.yaml)
    row = report.check("nrmsd_com_z", 3.64)
    assert (row.id, row.status) == ("nrmsd_com_z", report.REPRODUCED)
    assert report.check("nrmsd_com_z", 3.66).status == report.DIFFERS
    with pytest.raises(ValueError, match="not finite"):
        report.check("nrmsd_com_z", float("nan"))
    path = tmp_path / "part.csv"
    report.write_rows([row], path)
    df = report.combine([path], tmp_path / "all.csv")
    assert report.summary(df) == {"reproduced": 1, "consistent": 0, "calibrated": 0,
                                  "differs": 0, "not reproducible here": 0}
