"""Rider-control layer (pedalrepro.rider): the Hess, Moore & Hubbard (2012) loops and the
HumanControl gain rules, checked against HumanControl's published gain table."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import params, paths, response
from pedalrepro.rider import closed_loop, gains, plant


@pytest.fixture(scope="module")
def published_gains() -> dict:
    return params.read_yaml(paths.PUBLISHED / "humancontrol_gains.yaml")


def _row(table: list, speed: float) -> np.ndarray:
    rows = np.array(table, float)
    return rows[np.argmin(np.abs(rows[:, 0] - speed)), 1:]


def test_rules_give_benchmark_gains_at_5_m_s_within_1_percent(published_gains):
    model, geo = closed_loop.model_and_geometry("benchmark")
    res = gains.rule_gains(plant.plant(model, geo, 5.0))
    expected = _row(published_gains["Benchmark"], 5.0)
    np.testing.assert_allclose(res.gains, expected, rtol=0.01)
    # compute_inner_gains's own stored solution for this case: kDelta 46.5520, kPhiDot -0.05216
    assert res.gains[0] == pytest.approx(46.5520391, rel=1e-6)
    assert res.gains[1] == pytest.approx(-0.0521602768, rel=1e-5)


def test_rule_targets_hold_in_the_closed_loops():
    """The damping ratios and crossovers the rules ask for, recomputed independently."""
    model, geo = closed_loop.model_and_geometry("CF")
    p = plant.plant(model, geo, 25 / 3.6)
    k = gains.rule_gains(p).gains
    for loop, zeta in ((0, gains.ZETA_DELTA), (1, gains.ZETA_PHIDOT)):
        lam = np.linalg.eigvals(plant.closed_matrix(p, k, loop + 1))
        lam = lam[lam.imag > 0]
        assert np.min(np.abs(-lam.real / np.abs(lam) - zeta)) < 1e-9
    for loop, wc in zip((2, 3, 4), gains.CROSSOVER_RAD_S, strict=True):
        assert k[loop] * abs(plant.open_loop_response(p, k, loop, [wc])[0]) == pytest.approx(1.0)


def test_heading_kinematics_is_the_whipple_yaw_rate():
    """psi' = (v steer + c steer') cos(lam) / w (Meijaard et al. 2007), yP' = v psi."""
    model, geo = closed_loop.model_and_geometry("benchmark")
    p = plant.plant(model, geo, 4.0)
    x = np.zeros(plant.N_STATES)
    x[1], x[3], x[4] = 0.1, 0.2, 0.05
    dx = p.A @ x
    assert dx[4] == pytest.approx((4.0 * 0.1 + 0.08 * 0.2) * np.cos(np.pi / 10) / 1.02)
    assert dx[5] == pytest.approx(4.0 * 0.05)


def test_closed_loop_is_stable_where_the_open_loop_weave_is_not():
    sweep = closed_loop.gain_sweep("CF", np.array([3.0, 4.0, 5.0, 6.0]))
    assert sweep.stable.all()
    assert np.isfinite(sweep.gains).all()
    from pedalrepro import linear
    open_eig = linear.eigenvalues(linear.linear_model("CF"), np.array([3.0, 4.0, 5.0, 6.0]))
    assert (open_eig.real.max(axis=1) > 0).all()  # CF has no self-stable speed (Sec 3.2.1)


def test_closed_loop_particular_solution_matches_time_integration():
    """Steady-state cadence amplitude of the closed loop: batched solve vs solve_ivp (1e-6)."""
    from scipy.integrate import solve_ivp

    v, w = 25 / 3.6, 64 * 2 * np.pi / 60
    harm = response.forcing("CF", (1, 3, 5))
    k = closed_loop.rule_gains_at("CF", v).gains
    roll, steer = closed_loop.closed_loop_particular("CF", np.array([v]), k[None], np.array([w]),
                                                     harm)
    a_cl, p = closed_loop.closed_loop_matrices("CF", np.array([v]), k[None])
    n, coef = response.harmonic_coefficients(harm)
    force = p.B_f @ coef.T  # (8, k)

    def rhs(t, x):
        return a_cl[0] @ x + np.real(force @ ((n * w) ** 2 * np.exp(1j * n * w * t)))

    period = 2 * np.pi / w
    decay = -np.linalg.eigvals(a_cl[0]).real.max()
    t_end = np.ceil(40.0 / decay / period) * period  # transients decayed to exp(-40)
    t = t_end + np.linspace(0.0, period, 2049)[:-1]
    sol = solve_ivp(rhs, (0.0, t[-1]), np.zeros(plant.N_STATES), t_eval=t, rtol=1e-11,
                    atol=1e-14, method="DOP853")
    for idx, q in ((0, roll[0, 0]), (1, steer[0, 0])):
        x = sol.y[idx]
        amp1 = 2 * abs(np.mean(x * np.exp(-1j * w * t)))  # the cadence harmonic
        assert amp1 == pytest.approx(abs(q[0]), rel=1e-6)
        steady = np.real(np.exp(1j * np.outer(t, n * w)) @ q)
        assert np.max(np.abs(x - steady)) < 1e-6 * np.max(np.abs(steady))


def test_zero_steer_stiffness_is_the_open_loop_particular_solution():
    """kDelta = 0 with only the steer loop closed: the rider adds nothing (Eq 3.10-3.15)."""
    from pedalrepro import linear
    from pedalrepro.rider import comparison

    v, rpm = 25 / 3.6, 64.0
    sw = comparison.steer_stiffness_sweep("CF", v, rpm, np.array([0.0, 40.0]))
    h = response.forcing("CF", (1, 3, 5))
    r, s = response.particular_solution(linear.linear_model("CF"), v, rpm * np.pi / 30, h)
    assert sw.roll_rad.iloc[0] == pytest.approx(abs(r[0]), rel=1e-9)
    assert sw.steer_rad.iloc[0] == pytest.approx(abs(s[0]), rel=1e-9)
    assert sw.steer_rad.iloc[1] < sw.steer_rad.iloc[0]  # a stiffer steer moves less


def test_table_4_2_closed_is_median_and_range_of_the_rows():
    import pandas as pd

    from pedalrepro.rider import comparison

    val = pd.DataFrame({"system": ["CF"] * 6, "source": ["s"] * 6,
                        "quantity": ["roll"] * 3 + ["steer"] * 3,
                        "rd_open_percent": [10.0, 30.0, 80.0, 5.0, 7.0, 9.0],
                        "rd_closed_percent": [1.0, np.nan, 3.0, 2.0, 2.0, 2.0]})
    t = comparison.table_4_2_closed(val).iloc[0]
    assert t.n_points == 3
    assert (t.roll_rd_open_median_percent, t.roll_rd_open_range_percent) == (30.0, 70.0)
    assert (t.roll_rd_closed_median_percent, t.roll_rd_closed_range_percent) == (2.0, 2.0)
    assert (t.steer_rd_open_median_percent, t.steer_rd_open_range_percent) == (7.0, 4.0)


def test_roll_torque_rider_with_published_roll_gains_is_stable_on_the_benchmark():
    """HumanControl's roll-input gains (BenchmarkRollGains.txt) stabilise the benchmark at their
    speeds: the structure of the roll-torque (hands-free stand-in) loop matches theirs."""
    v = np.array([5.0, 6.0, 8.0, 10.0])
    g = closed_loop.published_gains("BenchmarkRoll", v)
    np.testing.assert_allclose(g[:, 1], [55.0, 157.0, 169.0, 171.0])
    a, _ = closed_loop.closed_loop_matrices("benchmark", v, g, "roll")
    assert (np.linalg.eigvals(a).real.max(axis=1) < 0).all()
    assert np.isnan(closed_loop.published_gains("BenchmarkRoll", np.array([4.0]))).all()


def test_bad_control_input_names_the_argument():
    model, geo = closed_loop.model_and_geometry("CF")
    with pytest.raises(ValueError, match="control_input"):
        plant.plant(model, geo, 5.0, control_input="lean")
    with pytest.raises(KeyError, match="unknown rider-control model"):
        closed_loop.model_and_geometry("nonexistent_bicycle")


def test_closed_loop_time_history_matches_solve_ivp_from_rest():
    """The analytic closed-loop time history (particular + homogeneous) against solve_ivp."""
    from scipy.integrate import solve_ivp

    v, w = 20 / 3.6, 70 * np.pi / 30
    harm = response.forcing("CF", (1, 3, 5))
    k = closed_loop.rule_gains_at("CF", v).gains
    t = np.linspace(0.0, 8.0, 801)
    roll, steer = closed_loop.closed_loop_time("CF", v, k, w, harm, t)
    a_cl, p = closed_loop.closed_loop_matrices("CF", np.array([v]), k[None])
    n, coef = response.harmonic_coefficients(harm)
    force = p.B_f @ coef.T

    def rhs(tt, x):
        return a_cl[0] @ x + np.real(force @ ((n * w) ** 2 * np.exp(1j * n * w * tt)))

    sol = solve_ivp(rhs, (0.0, t[-1]), np.zeros(plant.N_STATES), t_eval=t, rtol=1e-11,
                    atol=1e-14, method="DOP853")
    assert abs(roll[0]) < 1e-15 and abs(steer[0]) < 1e-15
    for got, ref in ((roll, sol.y[0]), (steer, sol.y[1])):
        assert np.max(np.abs(got - ref)) < 1e-6 * np.max(np.abs(ref))


def test_inner_damping_rule_has_no_solution_on_the_roll_torque_input():
    """Why the hands-free stand-in uses published gains: closing the roll-rate loop on the roll
    torque, the lightly damped closed-loop pair stays at damping 0.16-0.18 for kPhiDot 10-300
    (benchmark, 5 m/s), never the rule's 0.0855."""
    model, geo = closed_loop.model_and_geometry("benchmark")
    p = plant.plant(model, geo, 5.0, control_input="roll")
    damping = []
    for k in np.geomspace(10.0, 300.0, 25):
        lam = np.linalg.eigvals(plant.closed_matrix(p, np.array([1.0, k, 0, 0, 0]), 2))
        lam = lam[lam.imag > 0.5]
        damping.append(np.min(-lam.real / np.abs(lam)))
    assert 0.16 < min(damping) and max(damping) < 0.18
