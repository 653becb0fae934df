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
