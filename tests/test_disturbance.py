"""Generalised pedalling torques (Eq 2.15, 2.22, 2.24, 3.14) and the Table 4.1 model check."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import disturbance, legs, params

M_L_KG = 11.792  # Table D.1 caption: 0.2 + 4.392 + 7.2 (independent of legs.yaml)
L_HH_M = 0.26    # Moore 2009 rider model (DESIGN.md)


def _table_4_1_amplitudes(pub):
    """Independent 2x2 particular solution at the cadence harmonic (Eq 3.10-3.14)."""
    out = []
    for i, system in enumerate(pub["system"]):
        model = params.appendix_b_model(system)
        h = disturbance.torque_harmonics(params.BICYCLE_OF_MODEL[system], "O", harmonics=(1,))
        v = pub["speed_kmh"][i] / 3.6
        w = pub["cadence_rpm"][i] * 2.0 * np.pi / 60.0
        a = -(w**2) * model.M + 1j * w * v * model.C1 + model.g * model.K0 + v**2 * model.K2
        f = np.array([h.roll[0], h.steer[0]]) * w**2
        out.append(np.abs(np.linalg.solve(a, f)))
    return np.array(out)


def test_table_4_1_model_columns_from_eq_3_14(published):
    """Signs and magnitudes of Eq 3.14 against the 14 published Table 4.1 model numbers.

    13 of the 14 round to the published 3 decimals. HR at 25 km/h, steer, gives 0.020495 rad
    where the thesis prints 0.021: 5e-6 rad below the rounding boundary (a 0.025 % difference;
    e.g. m_L = 11.8 kg instead of 11.792 kg would round all 14). It is allowed a 1.1e-5 rad slack
    beyond the half-unit and reported. A sign error in the steer torque (or a time reversal,
    i.e. conjugated phases) changes the amplitudes by 40-150 % and fails every column.
    """
    pub = published["table_4_1_model_validation"]
    q = _table_4_1_amplitudes(pub)
    expected = np.column_stack([pub["roll_model_rad"], pub["steer_model_rad"]])
    dev = np.abs(q - expected)
    ok = dev <= 0.0005 + 1e-12
    assert ok.sum() == 13, dev
    col = pub["columns"].index("HR_25")
    assert not ok[col, 1]
    assert dev[col, 1] <= 0.0005 + 1.1e-5


def test_torque_harmonics_are_eq_3_14():
    g = params.steer_geometry("hybrid")
    factor = g["c"] * np.cos(g["lam"]) / g["w"]
    x, z = legs.com_fourier(legs.leg_geometry("hybrid", "O"), (1, 3, 5))
    h = disturbance.torque_harmonics("hybrid")
    assert list(h.n) == [1, 3, 5]
    np.testing.assert_allclose(h.roll, M_L_KG * L_HH_M * z, rtol=1e-13)
    np.testing.assert_allclose(h.steer, -factor * M_L_KG * L_HH_M * x, rtol=1e-13)
    # time form: f = sum m_L l_hh (n w)^2 |Z| cos(n w t + angle Z)
    w = 2 * np.pi
    t = np.linspace(0, 1, 7)
    roll, steer = h.evaluate(t, w)
    ref = sum(M_L_KG * L_HH_M * (n * w) ** 2 * abs(zn) * np.cos(n * w * t + np.angle(zn))
              for n, zn in zip((1, 3, 5), z, strict=True))
    np.testing.assert_allclose(roll, ref, rtol=1e-12)
    ref_s = sum(-factor * M_L_KG * L_HH_M * (n * w) ** 2 * abs(xn)
                * np.cos(n * w * t + np.angle(xn))
                for n, xn in zip((1, 3, 5), x, strict=True))
    np.testing.assert_allclose(steer, ref_s, rtol=1e-12)


def test_benchmark_uses_hybrid_legs_and_benchmark_steer_geometry():
    hb = disturbance.torque_harmonics("benchmark")
    hh = disturbance.torque_harmonics("hybrid")
    np.testing.assert_allclose(hb.roll, hh.roll, rtol=1e-14)
    ratio = disturbance.steer_factor("benchmark") / disturbance.steer_factor("hybrid")
    np.testing.assert_allclose(hb.steer, hh.steer * ratio, rtol=1e-13)
    b = params.benchmark_parameters("benchmark")
    assert disturbance.steer_factor("benchmark") == pytest.approx(
        b["c"] * np.cos(b["lam"]) / b["w"], rel=1e-14)


def test_bad_bicycle_and_com_are_clear_errors():
    with pytest.raises(ValueError, match="unknown bicycle"):
        disturbance.torque_harmonics("tandem")
    with pytest.raises(ValueError, match="unknown COM model"):
        disturbance.torque_harmonics("hybrid", com="X")
