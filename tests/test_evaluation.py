"""Evaluation points, RD (Eq 3.26) and gear ratios (Sec 3.1.3)."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import evaluation, gears, linear


def test_relative_difference_eq_3_26():
    rd = evaluation.relative_difference(np.array([2.0, 0.0, 1.0]), np.array([1.0, 1.0, -1.5]))
    assert rd[0] == pytest.approx(50.0)
    assert np.isnan(rd[1])  # zero reference: undefined, not a silent 0
    assert rd[2] == pytest.approx(50.0)  # amplitudes: absolute values


@pytest.mark.parametrize("model", ["HS", "CF", "HR", "CR"])
def test_example_points_on_gear_ratio_2_3(model):
    pts = evaluation.example_points(model)
    assert len(pts.speed_m_s) == 6
    gr = gears.gear_ratio(pts.speed_m_s, pts.omega_rad_s,
                          gears.wheel_radius_m(linear.bicycle_of(model)))
    np.testing.assert_allclose(gr, pts.gear_ratio, rtol=1e-12)
    assert 2.25 < pts.gear_ratio < 2.45  # "~2.3 medium gearing ratio" (Sec 3.2.1)
    # on the time grid (v = 0:0.4:10, w = 0:0.5:4 pi)
    np.testing.assert_allclose(pts.speed_m_s / 0.4, np.round(pts.speed_m_s / 0.4), atol=1e-9)
    np.testing.assert_allclose(pts.omega_rad_s / 0.5, np.round(pts.omega_rad_s / 0.5), atol=1e-9)
    assert pts.speed_m_s.max() <= 10 and pts.omega_rad_s.max() <= 4 * np.pi


def test_example_point_3_of_hs_shows_a_3_s_weave():
    """Sec 3.2.1: point 3 of HS has a growing weave of period ~3 s (~2.1 rad/s)."""
    pts = evaluation.example_points("HS")
    e = linear.eigenvalues(linear.linear_model("HS"), pts.speed_m_s[2])
    weave = e[np.argmax(np.abs(e.imag))]
    assert 0 < weave.real < 0.5
    assert 2 * np.pi / abs(weave.imag) == pytest.approx(3.0, abs=0.3)


def test_stable_mask_and_stats():
    v = np.array([4.0, 5.0, 6.0, 7.0, 8.0])
    mask = evaluation.stable_speed_mask("HR", v)
    assert mask.tolist() == [False, True, True, True, False]
    st = evaluation.rd_stats(np.array([1.0, 2.0, np.nan, 10.0]), np.array([1, 1, 1, 0], bool))
    assert (st.median, st.minimum, st.maximum, st.count) == (1.5, 1.0, 2.0, 2)
    assert evaluation.rd_stats(np.array([1.0]), np.array([False])) is None
    assert not evaluation.stable_speed_mask("CF", np.linspace(0, 10, 11)).any()


def test_gears_and_ellipse():
    r = 0.34
    assert gears.speed_m_s(2.0, 2 * np.pi, r) == pytest.approx(4 * np.pi * r)
    assert gears.cadence_rad_s(2.0, 4 * np.pi * r, r) == pytest.approx(2 * np.pi)
    v, w = gears.normal_cycling_ellipse((14, 22), (50, 80))
    assert v.min() == pytest.approx(14 / 3.6, rel=1e-3)  # sampled curve: extremes to 1e-3
    assert w.max() == pytest.approx(80 * np.pi / 30, rel=1e-3)
    assert gears.inside_ellipse(5.0, 2 * np.pi, (14, 22), (50, 80))  # the reference point
    assert not gears.inside_ellipse(9.0, 2 * np.pi, (14, 22), (50, 80))


def test_one_speed_series_just_below_the_self_stable_range():
    """Fig 3.18/3.19/3.28/3.29 (issue 25, part 4): the series speed is the fastest numbered
    example point below the model's self-stable range (Sec 3.2.2, "just below the self-stable
    range"), from the eigenvalues: HS gets point 3 (the thesis's Fig 3.18 is at point 3's speed);
    CR gets a point below its range, where its weave real part is positive; CF (no self-stable
    range) keeps point 3."""
    import numpy as np

    from pedalrepro import evaluation, linear

    grid = np.arange(0.0, 15.0, 0.01)
    for model in ("HS", "HR", "CR"):
        pts = evaluation.example_points(model)
        start = linear.stable_ranges(linear.linear_model(model), grid)[0][0]
        v = pts.series_speed_m_s
        assert v < start and v in pts.speed_m_s
        assert not np.any((pts.speed_m_s > v) & (pts.speed_m_s < start))  # the fastest below
        e = linear.eigenvalues(linear.linear_model(model), np.array([v]))[0]
        weave = e[np.abs(e.imag) > 1e-9]
        assert weave.real.max() > 0  # the weave is unstable there: the point of the figures
    assert abs(evaluation.example_points("HS").series_speed_m_s - 5.6) < 1e-9
    assert abs(evaluation.example_points("CR").series_speed_m_s - 4.4) < 1e-9
    cf = evaluation.example_points("CF")
    assert cf.series_speed_m_s == cf.speed_m_s[2]
