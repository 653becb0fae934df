"""Time integration (pedalrepro.integrator): fall events keep the simulated part, non-finite
states stop with an error, the compiled Dormand-Prince run equals solve_ivp's RK45."""

from __future__ import annotations

import types

import numpy as np
import pytest
from required import CC, skip_unless_required

from pedalrepro.integrator import (
    LinearSystem,
    SimulationError,
    flow,
    harmonic_torque,
    integrate,
)
from pedalrepro.nonlinear.simulate import simulate


def _inverted(a: float = 4.0) -> LinearSystem:
    """Linear inverted pendulum roll'' = a roll, unforced: falls in a known time."""
    return LinearSystem(np.array([[0.0, 1.0], [a, 0.0]]), np.zeros(0), np.zeros((0, 1)), (1,))


@pytest.mark.parametrize("compiled,variant", [(False, "scipy"), (True, "scipy"),
                                              (True, "hermite")])
def test_fall_event_stops_and_keeps_the_simulated_part(compiled, variant):
    system = _inverted()
    if compiled and system.compiled() is None:
        skip_unless_required(CC, "no C compiler")
    t = np.arange(1001) / 100.0
    sim = integrate(system, np.array([1e-3, 0.0]), t, rtol=1e-10, atol=1e-12,
                    fall_roll_rad=1.0, compiled=compiled, variant=variant)
    # roll = 1e-3 cosh(2 t) reaches 1 rad at t = acosh(1000) / 2; local errors below
    # rtol = 1e-10 over ~1e3 steps, amplified by the growth: well within 1e-6 relative
    assert sim.fell
    assert sim.t_end_s == pytest.approx(np.arccosh(1000.0) / 2.0, rel=1e-6)
    kept = sim.t_s <= sim.t_end_s
    assert np.all(np.isfinite(sim.roll_rad[kept]))
    assert np.all(np.isnan(sim.roll_rad[~kept]))
    np.testing.assert_allclose(sim.roll_rad[kept], 1e-3 * np.cosh(2 * sim.t_s[kept]), rtol=1e-7)


@pytest.mark.parametrize("compiled", [True, False])
def test_flow_over_an_interval_without_samples(compiled):
    """flow(): the state at t1 from t0 (0.5 -> 2 s on the pendulum: exact cosh/sinh)."""
    system = _inverted()
    x0 = np.array([1e-3 * np.cosh(1.0), 2e-3 * np.sinh(1.0)])
    x1 = flow(system, x0, 0.5, 2.0, rtol=1e-11, atol=1e-14,
              method="RK45" if compiled else "DOP853")
    np.testing.assert_allclose(x1, [1e-3 * np.cosh(4.0), 2e-3 * np.sinh(4.0)], rtol=1e-8)


def test_non_finite_state_is_an_error():
    bad = types.SimpleNamespace(roll_index=0, steer_index=1, steer_limit_rad=np.inf,
                                rhs=lambda t, x: np.array([np.nan, 0.0]), compiled=lambda: None)
    with pytest.raises(SimulationError, match="non-finite"):
        integrate(bad, np.zeros(2), np.linspace(0, 1, 11), rtol=1e-6, atol=1e-8,
                  fall_roll_rad=1.0)


def test_bad_arguments_name_the_argument():
    with pytest.raises(ValueError, match="rtol"):
        integrate(_inverted(), np.zeros(2), np.linspace(0, 1, 3), rtol=np.nan, atol=1e-8,
                  fall_roll_rad=1.0)
    with pytest.raises(ValueError, match="t_s"):
        integrate(_inverted(), np.zeros(2), np.array([0.0, 0.0]), rtol=1e-3, atol=1e-8,
                  fall_roll_rad=1.0)
    with pytest.raises(ValueError, match="variant"):
        integrate(_inverted(), np.zeros(2), np.linspace(0, 1, 3), rtol=1e-3, atol=1e-8,
                  fall_roll_rad=1.0, variant="euler")


def test_harmonic_torque_matches_eq_3_14():
    h = types.SimpleNamespace(n=np.array([1, 3]), roll=np.array([2 + 1j, 0.5]),
                              steer=np.array([0.1j, 0.0]))
    f = harmonic_torque(h, 2.0)
    t = 0.3
    roll = (2 + 1j) * 4 * np.exp(2j * t) + 0.5 * 36 * np.exp(6j * t)
    steer = 0.1j * 4 * np.exp(2j * t)
    assert f(t) == pytest.approx((roll.real, steer.real), rel=1e-12)


def test_compiled_run_equals_solve_ivp_rk45():
    """The compiled Dormand-Prince run reproduces solve_ivp(RK45) on the NT model, fall included
    (both variants; the scipy variant takes solve_ivp's steps, so it agrees to round-off)."""
    from pedalrepro import response
    from pedalrepro.nonlinear import models

    nl = models.nt_model("HR")
    if nl.lib is None:
        skip_unless_required(CC, "no C compiler")
    h = response.forcing("HR", None)
    kw = dict(harmonics=h, omega_rad_s=6.0, rtol=1e-8, atol=1e-10)
    ref = simulate(nl, 6.0, 20.0, 50.0, compiled=False, **kw)
    scale = np.max(np.abs(ref.roll_rad))
    for variant, tol in (("hermite", 1e-7), ("scipy", 1e-9)):
        fast = simulate(nl, 6.0, 20.0, 50.0, variant=variant, **kw)
        assert not fast.fell
        np.testing.assert_allclose(fast.roll_rad, ref.roll_rad, atol=tol * scale)
    ref_fall = simulate(nl, 2.0, 20.0, 50.0, compiled=False, fall_roll_rad=1.0, **kw)
    assert ref_fall.fell
    for variant in ("hermite", "scipy"):
        falling = simulate(nl, 2.0, 20.0, 50.0, fall_roll_rad=1.0, variant=variant, **kw)
        assert falling.fell
        assert falling.t_end_s == pytest.approx(ref_fall.t_end_s, abs=1e-6)
        kept = falling.t_s <= falling.t_end_s
        assert np.all(np.isfinite(falling.roll_rad[kept]))
        assert np.all(np.isnan(falling.roll_rad[~kept]))
