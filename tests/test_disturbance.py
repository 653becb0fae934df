"""Generalised pedalling torques (Eq 2.15, 2.22, 2.24, 3.14) and the Table 4.1 model check."""

from __future__ import annotations

from dataclasses import replace

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


def _harmonic_amplitudes(signal: np.ndarray) -> np.ndarray:
    """|DFT| of one revolution per harmonic (rows: n = 0..N/2), columns as in ``signal``."""
    return np.abs(np.fft.rfft(signal, axis=0)) * 2 / signal.shape[0]


@pytest.fixture(scope="module")
def hybrid60():
    return disturbance.pedalling_disturbance("hybrid", "O", 2 * np.pi, samples_per_revolution=720)


def test_forces_even_torques_odd_to_machine_precision(hybrid60):
    """Sec 2.2.2 and Appendix B.2: legs pi out of phase cancel odd (forces, pitch) or even
    (roll, yaw) multiples of the cadence."""
    d = hybrid60
    f = _harmonic_amplitudes(d.force_n[:, [0, 2]])
    t = _harmonic_amplitudes(d.torque_nm)
    odd, even = slice(1, None, 2), slice(2, None, 2)
    assert np.max(f[odd]) < 1e-13 * np.max(f)
    assert np.max(t[odd, 1]) < 1e-13 * np.max(t[:, 1])            # pitch: even only (B.31)
    assert np.max(t[even][:, [0, 2]]) < 1e-13 * np.max(t[:, [0, 2]])  # roll, yaw: odd only
    assert np.max(t[0, [0, 2]]) < 1e-13 * np.max(t[:, [0, 2]])
    # the dominant components: forces at 2 omega, roll and yaw at omega
    assert np.argmax(f[:, 0]) == 2 and np.argmax(f[:, 1]) == 2
    assert np.argmax(t[:, 0]) == 1 and np.argmax(t[:, 2]) == 1
    # the cadence-only motion has no even multiples: its forces cancel exactly (Sec 2.2.2)
    assert np.max(np.abs(d.force_simple_n)) < 1e-12


def test_time_domain_torques_equal_eq_2_22_and_3_14(hybrid60):
    """Eq 2.9 + 2.15 in the time domain equal the harmonic sum of Eq 2.22/2.24 (all odd n)."""
    d = hybrid60
    odd = tuple(range(1, 360, 2))
    h = disturbance.torque_harmonics("hybrid", "O", odd, samples_per_revolution=720)
    roll, steer = h.evaluate(d.t_s, d.cadence_rad_s)
    np.testing.assert_allclose(roll, d.generalised_nm[:, 0], atol=1e-12 * np.ptp(roll))
    np.testing.assert_allclose(steer, d.generalised_nm[:, 1], atol=1e-12 * np.ptp(steer))
    # and the cadence-only torques are the n = 1 term alone
    h1 = disturbance.torque_harmonics("hybrid", "O", (1,), samples_per_revolution=720)
    r1, s1 = h1.evaluate(d.t_s, d.cadence_rad_s)
    np.testing.assert_allclose(r1, d.generalised_simple_nm[:, 0], atol=1e-12 * np.ptp(r1))
    np.testing.assert_allclose(s1, d.generalised_simple_nm[:, 1], atol=1e-12 * np.ptp(s1))


def test_roll_torque_sign_physics():
    """Roll positive to the right: when the right leg accelerates upwards (a_z < 0, z down) the
    reaction pushes the right side down, a positive (rightward) roll torque."""
    d = disturbance.pedalling_disturbance("hybrid", samples_per_revolution=360)
    az_right = d.right.com_acc[:, 1]
    az_left = d.left.com_acc[:, 1]
    # the lumped roll torque is -(l_hh/2) m_L (az_right - az_left)
    expected = -0.5 * L_HH_M * M_L_KG * (az_right - az_left)
    np.testing.assert_allclose(d.torque_nm[:, 0], expected, rtol=1e-12, atol=1e-12)
    i = np.argmin(az_right - az_left)
    assert d.torque_nm[i, 0] > 0


def test_torques_scale_with_omega_squared_leg_mass_and_hip_width():
    base = disturbance.pedalling_disturbance("city", "W", 4.0, samples_per_revolution=360)
    fast = disturbance.pedalling_disturbance("city", "W", 12.0, samples_per_revolution=360)
    np.testing.assert_allclose(fast.generalised_nm, 9.0 * base.generalised_nm, rtol=1e-12,
                               atol=1e-12)
    np.testing.assert_allclose(fast.torque_nm, 9.0 * base.torque_nm, rtol=1e-11, atol=1e-11)
    np.testing.assert_allclose(fast.force_n, 9.0 * base.force_n, rtol=1e-11, atol=1e-11)
    geo = legs.leg_geometry("city", "W")
    heavy = replace(geo, crank_mass_kg=1.5 * geo.crank_mass_kg,
                    shank_mass_kg=1.5 * geo.shank_mass_kg, thigh_mass_kg=1.5 * geo.thigh_mass_kg)
    d_heavy = disturbance.pedalling_disturbance("city", "W", 4.0, samples_per_revolution=360,
                                                geometry=heavy)
    np.testing.assert_allclose(d_heavy.generalised_nm, 1.5 * base.generalised_nm, rtol=1e-12,
                               atol=1e-13)
    wide = replace(geo, hip_width_m=2.0 * geo.hip_width_m)
    d_wide = disturbance.pedalling_disturbance("city", "W", 4.0, samples_per_revolution=360,
                                               geometry=wide)
    np.testing.assert_allclose(d_wide.generalised_nm, 2.0 * base.generalised_nm, rtol=1e-12,
                               atol=1e-13)
    np.testing.assert_allclose(d_wide.force_n, base.force_n, atol=1e-12)


def test_segment_inertia_enters_pitch_only():
    kw = {"samples_per_revolution": 360}
    g = legs.leg_geometry("hybrid")
    r = legs.leg_motion(g, 2 * np.pi, **kw)
    le = legs.leg_motion(g, 2 * np.pi, left=True, **kw)
    with_i = disturbance.dalembert_torques_nm(r, le, g, inertia=True)
    without = disturbance.dalembert_torques_nm(r, le, g, inertia=False)
    np.testing.assert_array_equal(with_i[:, [0, 2]], without[:, [0, 2]])
    inertia = disturbance.segment_pitch_inertia_kg_m2(g)
    assert inertia["thigh"] == pytest.approx(7.2 * 0.46**2 / 12, rel=1e-14)
    expected = -sum(inertia[s] * (r.pitch_acc_rad_s2[s] + le.pitch_acc_rad_s2[s])
                    for s in legs.SEGMENTS)
    np.testing.assert_allclose(with_i[:, 1] - without[:, 1], expected, atol=1e-12)


def test_segment_model_forces_equal_lumped_model():
    """Per-segment d'Alembert forces sum to the leg-COM force (Eq 2.3 is the mass-weighted mean)."""
    g = legs.leg_geometry("hybrid", "W")
    r = legs.leg_motion(g, 3.0, samples_per_revolution=360)
    force_segments = -sum(m * r.segment_com_acc[s] for s, m in legs.segment_masses_kg(g).items())
    np.testing.assert_allclose(force_segments, -g.leg_mass_kg * r.com_acc, atol=1e-12)


def test_section2_numbers_match_the_thesis_claims():
    """Sec 2.2: NRMSD 2 % / 3.6 % (COM), 3.4 % / 8.2 % (torques) at 60 rpm on the hybrid, to the
    published rounding; forces 'about 12 N' / 'about 39 N' (errata 12); O vs W 'about 2 %'."""
    s = disturbance.section2_numbers("hybrid", 2 * np.pi, samples_per_revolution=720)
    assert s["nrmsd_com_x_percent"] == pytest.approx(2.0, abs=0.05)
    assert s["nrmsd_com_z_percent"] == pytest.approx(3.6, abs=0.05)
    assert s["nrmsd_roll_torque_percent"] == pytest.approx(3.4, abs=0.05)
    assert s["nrmsd_steer_torque_percent"] == pytest.approx(8.2, abs=0.05)
    assert s["force_x_2w_amplitude_n"] == pytest.approx(12, rel=0.1)
    assert s["force_z_2w_amplitude_n"] == pytest.approx(39, rel=0.1)
    assert s["force_z_peak_n"] == pytest.approx(39, rel=0.1)
    assert s["ow_change_x1_percent"] == pytest.approx(2.0, abs=0.5)
    # errata 4: per-segment lateral positions do not give the published 8.2 %
    seg = disturbance.section2_numbers("hybrid", 2 * np.pi, 720, lateral="segments")
    assert seg["nrmsd_steer_torque_percent"] > 8.25


def test_nrmsd_independent_of_cadence():
    """Errata 7: every harmonic scales with (n omega)^2, so the NRMSDs do not depend on cadence."""
    a = disturbance.section2_numbers("city", 2.0, samples_per_revolution=360)
    b = disturbance.section2_numbers("city", 11.0, samples_per_revolution=360)
    for key in ("nrmsd_com_x_percent", "nrmsd_com_z_percent", "nrmsd_roll_torque_percent",
                "nrmsd_steer_torque_percent"):
        assert a[key] == pytest.approx(b[key], rel=1e-12)
    assert b["force_x_peak_n"] == pytest.approx(a["force_x_peak_n"] * (11 / 2) ** 2, rel=1e-12)


def test_nrmsd_definition_and_errors():
    x = np.array([0.0, 1.0, 2.0, 1.0])
    assert disturbance.nrmsd_percent(x, x + 0.1) == pytest.approx(5.0)
    with pytest.raises(ValueError, match="constant reference"):
        disturbance.nrmsd_percent(np.ones(4), np.zeros(4))
    with pytest.raises(ValueError, match="even"):
        disturbance.pedalling_disturbance(samples_per_revolution=361)
    with pytest.raises(ValueError, match="unknown lateral"):
        disturbance.section2_numbers(lateral="x")
