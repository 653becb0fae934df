"""Particular, analytic and numerical time solutions of the linear models (Sec 3.1.2)."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import disturbance, linear, params, response, spectral

H = response.SimpleHarmonics(np.array([1, 3, 5]), np.array([0.5 + 0.2j, 0.02j, 0.001]),
                             np.array([-0.01 + 0.005j, 0.001, 0.0001j]))


def test_batched_particular_solution_equals_per_point_loop():
    model = linear.linear_model("HR")
    v = np.linspace(0, 10, 7)
    w = np.linspace(0, 4 * np.pi, 9)
    r, s = response.particular_solution(model, v[:, None], w[None, :], H)
    rl, sl = response.particular_solution_loop(model, v, w, H)
    np.testing.assert_allclose(r, rl, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(s, sl, rtol=1e-12, atol=1e-15)
    assert np.all(r[:, 0] == 0)  # no cadence, no forcing


def test_particular_solution_satisfies_equation_of_motion():
    """Substitute q_p into Eq 3.8 at a few instants (independent of the solver)."""
    model = linear.linear_model("CF")
    v, w = 4.3, 5.1
    r, s = response.particular_solution(model, v, w, H)
    q = np.stack([r, s])  # (2, k)
    for t in (0.0, 0.37, 1.9):
        ph = np.exp(1j * H.n * w * t)
        qt = np.real(q @ ph)
        qd = np.real(q @ (1j * H.n * w * ph))
        qdd = np.real(q @ (-(H.n * w) ** 2 * ph))
        f = np.real(np.stack([H.roll, H.steer]) @ ((H.n * w) ** 2 * ph))
        lhs = model.M @ qdd + v * model.C1 @ qd + (model.g * model.K0 + v**2 * model.K2) @ qt
        np.testing.assert_allclose(lhs, f, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("compiled", [True, False])
def test_analytic_time_solution_starts_at_rest_and_matches_tight_integration(compiled):
    """LA (exact, Eq 3.9/3.16-3.18) = LN at rtol 1e-10 to 1e-9 rad (the local errors of the
    integration, compiled Dormand-Prince or solve_ivp, summed over the run)."""
    model = linear.linear_model("HR")
    t = np.arange(0, 20.0 + 1e-9, 0.01)
    sol = response.analytic_time_solution(model, np.array([6.0]), np.array([5.0]), H, t)
    assert sol.roll_rad[0, 0, 0] == pytest.approx(0.0, abs=1e-14)
    assert (sol.roll_rad[0, 0, 1] - sol.roll_rad[0, 0, 0]) / 0.01 == pytest.approx(0, abs=1e-3)
    roll, steer, t_end, fell = response.numerical_time_solution(
        model, 6.0, 5.0, H, t, rtol=1e-10, atol=1e-12, compiled=compiled)
    assert not fell and t_end == 20.0
    np.testing.assert_allclose(roll, sol.roll_rad[0, 0], atol=1e-9)
    np.testing.assert_allclose(steer, sol.steer_rad[0, 0], atol=1e-9)


def test_compiled_ln_equals_solve_ivp_ln_at_the_ode45_tolerances():
    """LN through the compiled integrator takes solve_ivp's RK45 steps (same initial step, step
    rules, quartic dense output, fall event) at the thesis's ode45 tolerances (rtol 1e-3,
    atol 1e-6): 60 s runs agree to round-off, stable and falling, on the thesis grid's cadence
    and speeds; amplitudes at the cadence to 1e-9, fall times to 1e-9 s. (A round-off flip of
    one accept/reject decision would make them two valid RK45 solutions differing at the rtol
    level; these runs have none, checked by the tight bound.)"""
    model = linear.linear_model("HR")
    h = response.forcing("HR", None)
    t = np.arange(6001) / 100.0
    v, w = np.array([2.0, 6.0]), np.array([4.0, 6.0])
    kw = dict(rtol=1e-3, atol=1e-6, fall_roll_rad=np.pi / 2)
    fast = response.numerical_time_solutions(model, v, w, h, t, **kw)
    ref = response.numerical_time_solutions(model, v, w, h, t, compiled=False, **kw)
    assert fast.fell.any() and not fast.fell.all()  # both kinds of run are compared
    np.testing.assert_array_equal(fast.fell, ref.fell)
    np.testing.assert_allclose(fast.t_end_s, ref.t_end_s, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(np.isfinite(fast.roll_rad), np.isfinite(ref.roll_rad))
    ra, sa = response.cadence_amplitudes(fast, 100.0)
    rb, sb = response.cadence_amplitudes(ref, 100.0)
    np.testing.assert_allclose(ra, rb, rtol=1e-9)
    np.testing.assert_allclose(sa, sb, rtol=1e-9)


def test_fall_event_stops_and_keeps_what_was_simulated():
    model = linear.linear_model("HS")
    t = np.arange(0, 60.0 + 1e-9, 0.01)
    roll, steer, t_end, fell = response.numerical_time_solution(model, 1.0, 2.0, H, t)
    assert fell and 0 < t_end < 60
    kept = np.isfinite(roll)
    assert kept.sum() > 10 and np.all(np.abs(roll[kept]) < np.pi / 2)
    sol = response.analytic_time_solution(model, np.array([1.0]), np.array([2.0]), H, t)
    assert sol.fell[0, 0]
    assert sol.t_end_s[0, 0] == pytest.approx(t_end, abs=0.05)


def test_hann_dft_of_stable_time_solution_equals_particular_solution():
    """Evaluation point 3b in the self-stable region: the DFT amplitude -> PS amplitude."""
    model = linear.linear_model("HR")
    t = np.arange(0, 180.0, 0.01)
    sol = response.analytic_time_solution(model, np.array([6.0]), np.array([4.0, 8.0]), H, t)
    ra, sa = response.cadence_amplitudes(sol, 100.0)
    r, s = response.particular_solution(model, 6.0, np.array([4.0, 8.0]), H)
    np.testing.assert_allclose(ra[0], np.abs(r[:, 0]), rtol=1e-4)
    np.testing.assert_allclose(sa[0], np.abs(s[:, 0]), rtol=1e-4)
    x = sol.roll_rad[0, 1]
    assert spectral.amplitude_at(x, 100.0, 8.0 / (2 * np.pi)) == pytest.approx(ra[0, 1])


def test_benchmark_particular_solution_peaks_at_the_undamped_weave():
    """Fig G.7: maximum at 4.29 m/s and 3.43 rad/s (benchmark with hands-free pedalling legs)."""
    model = linear.linear_model("benchmark")
    h = disturbance.torque_harmonics("benchmark")
    v = response.grid(0.1, 10.0)
    w = response.grid(0.124, 4 * np.pi)
    r, s = response.particular_solution(model, v[:, None], w[None, :], h)
    for amp in (np.abs(r[..., 0]), np.abs(s[..., 0])):
        i, j = np.unravel_index(np.argmax(amp), amp.shape)
        assert v[i] == pytest.approx(4.29, abs=0.1 / 2 + 1e-9)
        assert w[j] == pytest.approx(3.43, abs=0.124 / 2 + 1e-9)


def test_table_4_1_model_columns(published):
    """13 of the 14 Table 4.1 model numbers round to the published 3 decimals.

    HR 25 km/h steer is 0.020495 rad where the thesis prints 0.021 (5e-6 rad below the rounding
    boundary; the same finding as tests/test_disturbance.py); allowed 1.1e-5 rad slack.
    """
    pub = published["table_4_1_model_validation"]
    got = []
    for system, v_kmh, c_rpm in zip(pub["system"], pub["speed_kmh"], pub["cadence_rpm"],
                                    strict=True):
        model = linear.linear_model(system)
        h = disturbance.torque_harmonics(params.BICYCLE_OF_MODEL[system])
        r, s = response.particular_solution(model, v_kmh / 3.6, c_rpm * np.pi / 30, h)
        got.append([abs(r[0]), abs(s[0])])
    dev = np.abs(np.array(got) - np.column_stack([pub["roll_model_rad"],
                                                  pub["steer_model_rad"]]))
    ok = dev <= 0.0005
    assert ok.sum() == 13
    assert dev.max() <= 0.0005 + 1.1e-5


def test_grid_matches_matlab_colon():
    assert len(response.grid(0.124, 4 * np.pi)) == 102
    assert len(response.grid(0.1, 10.0)) == 101
    assert len(response.grid(0.5, 4 * np.pi)) * len(response.grid(0.4, 10.0)) == 676


def test_solve_2x2_equals_lapack():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(50, 3, 2, 2)) + 1j * rng.normal(size=(50, 3, 2, 2))
    b = rng.normal(size=(50, 3, 2)) + 1j * rng.normal(size=(50, 3, 2))
    np.testing.assert_allclose(response.solve_2x2(a, b), np.linalg.solve(a, b[..., None])[..., 0],
                               rtol=1e-9)
