"""The chord start of the periodic-orbit Newton (OrbitSolver.solve, chord_start): the invariants
the faster maps rely on, no timings.

The chord steps use the shooting Jacobian of the model's own linearisation (matrix
exponentials of A(v)); Newton with the variational equations then starts on the orbit. The
orbit is the same zero of the same shooting equations, so it must equal the one Newton finds
from the PS without chord steps: both meet the residual tolerance (1e-10 of the orbit's size), so
amplitudes and phases agree to ~1e-10 and are checked at 1e-8. Floquet multipliers come from
forward-difference variational equations at different (converged) iterates: their rounding
noise is ~1e-8..1e-7 of the spectral radius (against central differences at rtol 1e-11), so
1e-6 of it as in tests/test_periodic.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from pedalrepro import linear, periodic
from pedalrepro.periodic.solver import small_expm

OMEGA = 2 * np.pi


def _match(a: np.ndarray, b: np.ndarray) -> float:
    return float(max(np.min(np.abs(a - m)) for m in b) / np.max(np.abs(b)))


def _assert_same_orbit(warm, cold) -> None:
    """Two solutions of the same shooting equations (module docstring: the tolerances)."""
    for key in ("roll_amplitude_rad", "steer_amplitude_rad", "hold_torque_mean_nm"):
        assert getattr(warm, key) == pytest.approx(getattr(cold, key), rel=1e-8)
    for key in ("roll_phase_rad", "steer_phase_rad"):
        assert getattr(warm, key) == pytest.approx(getattr(cold, key), abs=1e-8)
    assert _match(warm.floquet_multipliers, cold.floquet_multipliers) < 1e-6
    assert np.max(np.abs(warm.nodes - cold.nodes)) <= 1e-8 * np.max(np.abs(cold.nodes))


def test_expm_equals_scipy():
    """The scaling-and-squaring Taylor exponential against scipy's Pade one (both ~1e-15)."""
    rng = np.random.default_rng(3)
    for size in (0.1, 1.0, 10.0, 40.0):
        a = rng.normal(size=(4, 4)) * size
        ref = expm(a)
        assert np.max(np.abs(small_expm(a) - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_linear_jacobian_is_the_linear_limit_monodromy():
    """The chord Jacobian's monodromy (product of the segments' expm(A T_s / m), half-period
    sign) has the eigenvalues exp(lambda T_s) of the own linearisation, and equals the monodromy
    the variational equations give at the linear-limit orbit (torque x 1e-3: non-linear terms
    ~1e-10 relative, forward differences ~1e-8) to 1e-6 of its norm."""
    s = periodic.OrbitSolver("HR", "NT", OMEGA, torque_scale=1e-3)
    orb = s.solve(5.0, segments=1)
    J = s.linear_jacobian(5.0, 1)
    H = J + np.eye(4)  # one segment: J = sign G - I
    assert np.max(np.abs(H - orb.monodromy)) <= 1e-6 * np.max(np.abs(orb.monodromy))
    lam = linear.eigenvalues(s.linear, 5.0)
    assert _match(np.linalg.eigvals(H) ** 2, np.exp(lam * s.period_s)) < 1e-9


@pytest.mark.parametrize(("model", "method", "speed_m_s", "omega_rad_s"), [
    ("HR", "NT", 5.0, OMEGA),   # stable, single shooting, half period
    ("HR", "NT", 1.0, 1.5),     # capsize and weave unstable: multiple shooting
    ("CR", "NT", 5.2, 2.5),     # near the weave resonance: the largest non-linear share
    ("HR", "NP", 6.0, 5.5),     # legs moving: the linear Jacobian is further off
])
def test_chord_started_orbit_equals_newton_from_ps(model, method, speed_m_s, omega_rad_s):
    s = periodic.OrbitSolver(model, method, omega_rad_s)
    cold = s.solve(speed_m_s, chord_start=False)
    warm = s.solve(speed_m_s)
    assert cold.converged and warm.converged and warm.segments == cold.segments
    assert max(warm.periodicity_residual, cold.periodicity_residual) <= 1e-9
    _assert_same_orbit(warm, cold)


def test_chord_start_saves_variational_evaluations():
    """What the speed-up rests on: at a stable point the chord start needs fewer right-hand
    side evaluations (one evaluation with the variational equations instead of two)."""
    s = periodic.OrbitSolver("HR", "NT", OMEGA)
    cold = s.solve(5.0, chord_start=False)
    warm = s.solve(5.0)
    assert warm.n_rhs < cold.n_rhs


@pytest.mark.parametrize(("method", "omega_rad_s"), [("NT", OMEGA), ("NP", 5.5)])
def test_guided_orbit_is_the_same_orbit_whatever_the_neighbours(method, omega_rad_s):
    """The map's guides (OrbitSolver.solve guide/second: the converged orbits at the two next
    lower speeds) change only Newton's start and chord Jacobian, not the orbit: at 4.4 m/s the
    orbit guided by neighbours 0.2 m/s apart (the finer grid), 0.4 m/s apart (the thesis grid)
    and unguided (the PS start) agree to Newton's tolerance, as the chord-started one above. The
    guided chord Jacobian is closer to the orbit's own than the linearisation's (the speed-up:
    fewer chord steps), and for NP, where the linearisation leaves the legs' inertia out, the
    guided solve needs fewer right-hand-side evaluations."""
    s = periodic.OrbitSolver("HR", method, omega_rad_s)
    cold = s.solve(4.4)
    g36, g38, g40, g42 = (s.solve(v) for v in (3.6, 3.8, 4.0, 4.2))
    fine = s.solve(4.4, guide=g42, second=g40)
    coarse = s.solve(4.4, guide=g40, second=g36)
    assert all(o.converged for o in (cold, g36, g38, g40, g42, fine, coarse))
    for warm in (fine, coarse):
        assert warm.segments == cold.segments and warm.periodicity_residual <= 1e-9
        _assert_same_orbit(warm, cold)
    m = cold.segments
    own = cold.jacobian

    def off(jac):  # relative error of a chord Jacobian: the chord steps' contraction factor
        return np.linalg.norm(np.linalg.solve(jac, own - jac), 2)

    assert off(s.chord_jacobian(4.4, m, g42, g40)) < 0.1 * off(s.chord_jacobian(4.4, m))
    if method == "NP":
        assert fine.n_rhs < cold.n_rhs
