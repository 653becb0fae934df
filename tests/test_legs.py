"""Dual four-bar leg kinematics (Sec 2.1.1, Appendix B.1, Table D.1)."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import legs

CASES = ("hybrid_O", "hybrid_W", "city_O", "city_W")


@pytest.mark.parametrize("case", CASES)
def test_table_d_1_all_amplitudes_and_phases(case, published):
    """All 40 numbers of each Table D.1 column: 1e-6 relative (amplitude), 1e-6 rad (phase)."""
    pub = published["table_D1_leg_com_fourier"][case]
    bicycle, com = case.split("_")
    x, z = legs.com_fourier(legs.leg_geometry(bicycle, com), (1, 2, 3, 4, 5))
    for axis, coef in (("X", x), ("Z", z)):
        np.testing.assert_allclose(np.abs(coef), pub[f"amplitude_{axis}"], rtol=1e-6, atol=0)
        dphi = np.angle(np.exp(1j * (np.angle(coef) - np.array(pub[f"phase_{axis}"]))))
        assert np.max(np.abs(dphi)) < 1e-6


def test_city_original_seat_cannot_reach_the_pedal():
    """Sec 2.1.1: 0.77 m seat tube + post does not allow a full crank turn, 0.72 m does."""
    original = legs.leg_geometry("city", seat_tube_plus_post_m=0.77)
    with pytest.raises(ValueError, match=r"city \(O\), L = 0.77 m.*20.0 mm short.*37.6-99.4 deg"):
        legs.leg_motion(original, 2 * np.pi)
    legs.check_reach(legs.leg_geometry("city"))  # 0.72 m: no error
    # the unreachable range (errata 14): hip-pedal distance above l_ll + l_ul = 0.92 m
    bad = np.rad2deg(legs.unreachable_crank_angles_rad(original))
    assert bad.min() == pytest.approx(37.6, abs=0.05) and bad.max() == pytest.approx(99.4, abs=0.05)


def _spectral_derivative(x: np.ndarray, omega: float, order: int) -> np.ndarray:
    """Exact derivative of a sampled periodic signal (independent of the analytic one)."""
    n = x.shape[0]
    k = np.fft.fftfreq(n, d=1.0 / n)
    k[n // 2] = 0.0
    spec = np.fft.fft(x, axis=0) * ((1j * k * omega) ** order)[:, None]
    return np.real(np.fft.ifft(spec, axis=0))


@pytest.mark.parametrize("bicycle, com", [("hybrid", "O"), ("city", "W")])
def test_velocity_and_acceleration_are_exact(bicycle, com):
    """Analytic rates (differentiated loop closure) agree with spectral derivatives."""
    w = 2 * np.pi * 1.3
    m = legs.leg_motion(legs.leg_geometry(bicycle, com), w, samples_per_revolution=1024)
    for pos, vel, acc in [(m.com, m.com_vel, m.com_acc), (m.knee, None, None)] + [
            (m.segment_com[s], m.segment_com_vel[s], m.segment_com_acc[s]) for s in legs.SEGMENTS]:
        if vel is None:
            continue
        scale_v = np.max(np.abs(vel))
        scale_a = np.max(np.abs(acc))
        assert np.max(np.abs(_spectral_derivative(pos, w, 1) - vel)) < 1e-10 * scale_v
        assert np.max(np.abs(_spectral_derivative(pos, w, 2) - acc)) < 1e-9 * scale_a
    for s in ("shank", "thigh"):
        angle = np.unwrap(m.pitch_rad[s])
        rate, accel = m.pitch_rate_rad_s[s], m.pitch_acc_rad_s2[s]
        d1 = _spectral_derivative(angle[:, None], w, 1)[:, 0]
        d2 = _spectral_derivative(angle[:, None], w, 2)[:, 0]
        assert np.max(np.abs(d1 - rate)) < 1e-10 * np.max(np.abs(rate))
        assert np.max(np.abs(d2 - accel)) < 1e-8 * np.max(np.abs(accel))


def test_four_bar_closes_and_knee_is_forward():
    g = legs.leg_geometry("hybrid")
    m = legs.leg_motion(g, 2 * np.pi, samples_per_revolution=720)
    assert np.allclose(np.linalg.norm(m.knee - m.pedal, axis=1), g.shank_length_m, atol=1e-14)
    assert np.allclose(np.linalg.norm(m.hip - m.knee, axis=1), g.thigh_length_m, atol=1e-14)
    assert np.allclose(np.linalg.norm(m.pedal, axis=1), g.crank_length_m, atol=1e-15)
    # knee in front of the pedal-hip line (not hyper-extended, Fig 2.1)
    d = m.hip - m.pedal
    x_line = m.pedal[:, 0] + d[:, 0] * (m.knee[:, 1] - m.pedal[:, 1]) / d[:, 1]
    assert np.all(m.knee[:, 0] > x_line + 0.05)
    # right foot forward at t = 0, pedal moves down next (theta_A = -omega t, z down)
    assert m.pedal[0, 0] == pytest.approx(g.crank_length_m) and m.pedal[1, 1] > 0
    # hip behind and above the crank axis (errata 8)
    assert m.hip[0, 0] < 0 and m.hip[0, 1] < 0


def test_left_leg_is_right_leg_half_a_revolution_later():
    g = legs.leg_geometry("city", "W")
    n = 720
    r = legs.leg_motion(g, 5.0, samples_per_revolution=n)
    le = legs.leg_motion(g, 5.0, samples_per_revolution=n, left=True)
    np.testing.assert_allclose(le.com, np.roll(r.com, -n // 2, axis=0), atol=1e-15)
    np.testing.assert_allclose(le.com_acc, np.roll(r.com_acc, -n // 2, axis=0), atol=1e-12)


def test_com_fourier_independent_of_cadence_and_samples():
    g = legs.leg_geometry("hybrid")
    x1, z1 = legs.com_fourier(g, (1, 2, 3), samples_per_revolution=3600)
    x2, z2 = legs.com_fourier(g, (1, 2, 3), samples_per_revolution=720)
    np.testing.assert_allclose(x1, x2, rtol=1e-10)
    np.testing.assert_allclose(z1, z2, rtol=1e-10)
    m = legs.leg_motion(g, 9.0, samples_per_revolution=3600)
    np.testing.assert_allclose(legs.fourier_coefficients(m.com, (1, 2, 3))[:, 0], x1, rtol=1e-12)


def test_winter_changes_higher_harmonics_by_one_factor():
    """Errata 13: only the knee carries n >= 2, so W/O is one factor with equal phases."""
    xo, zo = legs.com_fourier(legs.leg_geometry("hybrid", "O"), (2, 3, 4, 5))
    xw, zw = legs.com_fourier(legs.leg_geometry("hybrid", "W"), (2, 3, 4, 5))
    ratio = np.concatenate([xw / xo, zw / zo])
    # independent: the knee's weight in the leg COM, (m_ll (1 - f_ll) + m_ul f_ul') with
    # f_ul' = 1 - f_ul (thigh COM measured from the knee), O vs W
    m_ll, m_ul = 4.392, 7.2
    knee_o = m_ll * 0.5 + m_ul * 0.5
    knee_w = m_ll * 0.394 + m_ul * (1 - 0.567)
    np.testing.assert_allclose(ratio, knee_w / knee_o, rtol=1e-9)


def test_fourier_coefficient_convention():
    t = np.arange(64) / 64 * 2 * np.pi
    x = 0.3 + 0.5 * np.cos(t + 0.2) + 0.1 * np.cos(3 * t - 1.0)
    c = legs.fourier_coefficients(x, (1, 2, 3))
    np.testing.assert_allclose(c, [0.5 * np.exp(0.2j), 0, 0.1 * np.exp(-1j)], atol=1e-15)
    with pytest.raises(ValueError, match="harmonics must lie"):
        legs.fourier_coefficients(x, (0,))
