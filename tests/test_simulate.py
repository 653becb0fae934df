"""Time integration: fall events keep the simulated part; non-finite states stop with an error."""

from __future__ import annotations

import types

import numpy as np
import pytest

from pedalrepro.simulate import SimulationError, harmonic_torque, simulate


class _Inverted:
    """Linear inverted pendulum roll'' = a roll: falls in a known time."""

    a = 4.0

    def upright_state(self, speed_m_s):
        return np.array([1e-3, 0.0])

    def rhs(self, t, x, torque=(0.0, 0.0)):
        return np.array([x[1], self.a * x[0] + torque[0]])


def test_fall_event_stops_and_keeps_the_simulated_part():
    sim = simulate(_Inverted(), 0.0, 10.0, 100.0, fall_roll_rad=1.0, rtol=1e-10, atol=1e-12)
    # roll = 1e-3 cosh(2 t) reaches 1 rad at t = acosh(1000) / 2
    assert sim.fell
    assert sim.t_end_s == pytest.approx(np.arccosh(1000.0) / 2.0, rel=1e-6)
    kept = sim.t_s <= sim.t_end_s
    assert np.all(np.isfinite(sim.roll_rad[kept]))
    assert np.all(np.isnan(sim.roll_rad[~kept]))
    np.testing.assert_allclose(sim.roll_rad[kept], 1e-3 * np.cosh(2 * sim.t_s[kept]), rtol=1e-7)


def test_non_finite_state_is_an_error():
    bad = _Inverted()
    bad.rhs = lambda t, x, torque=(0.0, 0.0): np.array([np.nan, 0.0])
    with pytest.raises(SimulationError, match="non-finite"):
        simulate(bad, 0.0, 1.0, 10.0)


def test_harmonic_torque_matches_eq_3_14():
    h = types.SimpleNamespace(n=np.array([1, 3]), roll=np.array([2 + 1j, 0.5]),
                              steer=np.array([0.1j, 0.0]))
    f = harmonic_torque(h, 2.0)
    t = 0.3
    roll = (2 + 1j) * 4 * np.exp(2j * t) + 0.5 * 36 * np.exp(6j * t)
    steer = 0.1j * 4 * np.exp(2j * t)
    assert f(t) == pytest.approx((roll.real, steer.real), rel=1e-12)


def test_compiled_run_equals_solve_ivp_rk45():
    """The compiled Dormand-Prince run reproduces solve_ivp(RK45) on the NT model, fall included."""
    from pedalrepro import response
    from pedalrepro.nonlinear import models
    from pedalrepro.simulate import simulate_compiled

    nl = models.nt_model("HR")
    if nl._lib is None:
        pytest.skip("no C compiler")
    h = response.forcing("HR", None)
    w = 6.0
    ref = simulate(nl, 6.0, 20.0, 50.0, torque=harmonic_torque(h, w), rtol=1e-8, atol=1e-10)
    fast = simulate_compiled(nl, 6.0, 20.0, 50.0, harmonics=h, omega_rad_s=w, rtol=1e-8,
                             atol=1e-10)
    assert not fast.fell
    scale = np.max(np.abs(ref.roll_rad))
    np.testing.assert_allclose(fast.roll_rad, ref.roll_rad, atol=1e-7 * scale)
    falling = simulate_compiled(nl, 2.0, 20.0, 50.0, harmonics=h, omega_rad_s=w, rtol=1e-8,
                                atol=1e-10, fall_roll_rad=1.0)
    ref_fall = simulate(nl, 2.0, 20.0, 50.0, torque=harmonic_torque(h, w), rtol=1e-8,
                        atol=1e-10, fall_roll_rad=1.0)
    assert falling.fell and ref_fall.fell
    assert falling.t_end_s == pytest.approx(ref_fall.t_end_s, abs=1e-6)
    kept = falling.t_s <= falling.t_end_s
    assert np.all(np.isfinite(falling.roll_rad[kept])) and np.all(np.isnan(falling.roll_rad[~kept]))
