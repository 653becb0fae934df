"""Conservation of angular momentum (Eq 3.19-3.25) and neglected momenta (Eq 3.29)."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import linear, momentum, response

H = response.SimpleHarmonics(np.array([1, 3, 5]), np.array([0.5 + 0.2j, 0.02j, 0.001]),
                             np.array([-0.01 + 0.005j, 0.001, 0.0001j]))


def _no_speed_no_gravity(model):
    return linear.LinearModel(model.name, model.M, 0 * model.C1, 0 * model.K0, 0 * model.K2)


def test_cam_is_the_particular_solution_without_speed_and_gravity():
    """Eq 3.20 vs Eq 3.8: with v = 0 and g = 0 the two methods coincide (Sec 3.1.2.3)."""
    model = linear.linear_model("HS")
    q = momentum.cam_coefficients(model, H)
    r, s = response.particular_solution(_no_speed_no_gravity(model), 0.0, 3.7, H)
    np.testing.assert_allclose(q[0], r, rtol=1e-12)
    np.testing.assert_allclose(q[1], s, rtol=1e-12)


def test_cam_amplitude_independent_of_cadence_and_momentum_balance():
    """Sec 3.2.3: CAM angles do not depend on cadence; M q' + L_L is constant (zero)."""
    model = linear.linear_model("CR")
    t = np.linspace(0, 3, 301)
    a1, r1 = momentum.cam_time(model, H, 2 * np.pi, t)
    a2, r2 = momentum.cam_time(model, H, 4 * np.pi, t / 2)
    np.testing.assert_allclose(a1, a2, atol=1e-14)  # same angle at the same crank angle
    np.testing.assert_allclose(r2, 2 * r1, atol=1e-12)  # rates scale with cadence
    # M q' = -L_L with L_L = -int f dt, checked numerically: d/dt (M q') = f
    w = 2 * np.pi
    f = np.real(np.stack([H.roll, H.steer]) @ (((H.n * w) ** 2)[:, None]
                                             * np.exp(1j * np.outer(H.n * w, t))))
    mqd = model.M @ r1
    np.testing.assert_allclose(np.gradient(mqd, t, axis=1)[:, 5:-5], f[:, 5:-5], rtol=0,
                               atol=2e-3 * np.abs(f).max())


def test_neglected_momenta_scaling():
    """Eq 3.29 terms scale as v/w, 1/w^2 and (v/w)^2 relative to the leg momentum."""
    model = linear.linear_model("HS")
    r1 = momentum.neglected_momenta_ratios(model, H, 2.0, 4.0)
    r2 = momentum.neglected_momenta_ratios(model, H, 4.0, 8.0)
    np.testing.assert_allclose(r2[0], r1[0], rtol=1e-12)  # v C1 q: v/w
    np.testing.assert_allclose(r2[1], r1[1] / 4, rtol=1e-12)  # g K0 int q: 1/w^2
    np.testing.assert_allclose(r2[2], r1[2], rtol=1e-12)  # v^2 K2 int q: (v/w)^2
    assert np.all(momentum.neglected_momenta_ratios(model, H, 0.0, 12.0)[0] == 0)


def test_neglected_momenta_are_small_only_at_low_speed_high_cadence():
    """Sec 3.2.3.1: all terms < 1/4 only at very low speed and high cadence (Fig 3.31)."""
    model = linear.linear_model("HS")
    h = response.forcing("HS")
    ok_corner = np.all(momentum.neglected_momenta_ratios(model, h, 0.2, 4 * np.pi) < 0.25)
    ok_normal = np.all(momentum.neglected_momenta_ratios(model, h, 5.0, 2 * np.pi) < 0.25)
    assert ok_corner and not ok_normal


def test_cam_amplitude_value():
    model = linear.linear_model("HR")
    roll, steer = momentum.cam_amplitude(model, H)
    q = -np.linalg.solve(model.M, np.array([H.roll[0], H.steer[0]]))
    assert roll == pytest.approx(abs(q[0])) and steer == pytest.approx(abs(q[1]))
