"""Parameters (pedalrepro.params): the Stratos steer geometry, the benchmark and browser bicycles,
the Appendix B mass matrices and the leg masses."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pedalrepro import params


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


def test_leg_mass_is_sum_of_segments():
    legs = params.legs()
    m = legs["crank_mass_kg"] + legs["shank_mass_kg"] + legs["thigh_mass_kg"]
    assert m == pytest.approx(11.792, abs=1e-12)


def test_one_model_list():
    """The model list is params.MODELS / params.LINEAR_MODELS; the two copies kept free of the
    parameter files (the figure registry, the validation figures) equal it, and every thesis
    model has an Appendix B model and a non-linear model."""
    from pedalrepro import linear
    from pedalrepro.figures import registry
    from pedalrepro.figures import validation as fval
    from pedalrepro.nonlinear import settings

    assert params.LINEAR_MODELS == ("benchmark", *params.MODELS)
    assert registry.MODELS4 == fval.SYSTEMS == params.MODELS
    assert linear.MODEL_NAMES == settings.NONLINEAR_MODELS == params.LINEAR_MODELS
    assert set(params.MODELS) == set(params.BICYCLE_OF_MODEL)
    assert set(params.MODELS) <= set(settings.settings()["models"])
