"""The hands-free lean-torque rider on Moore's leaning-rider plant (pedalrepro.rider.lean):
the plant against the Whipple model of the Browser with a rigid Jason, and the numbers that
show why the gain rules of pedalrepro.rider.gains give no stable loop on the lean input."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import params
from pedalrepro.rider import gains, lean, plant


def _rigid_browser_jason(speed: float) -> tuple[np.ndarray, np.ndarray]:
    """Meijaard et al. (2007) matrices (dtk) of HumanControl's Browser with a rigid Jason, the
    wheel Ixx as in BrowserBenchmark.txt (HumanControl's file has rear and front swapped)."""
    from dtk.bicycle import benchmark_par_to_canonical

    p = params.benchmark_parameters("humancontrol_browser")
    p["IRxx"], p["IFxx"] = p["IFxx"], p["IRxx"]
    m, c1, k0, k2 = benchmark_par_to_canonical(p)
    minv = np.linalg.inv(m)
    a = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-minv @ (p["g"] * k0 + speed**2 * k2), -speed * minv @ c1]])
    return a, np.vstack([np.zeros((2, 2)), minv])


@pytest.mark.parametrize("speed", [2.0, 5.0, 8.0])
def test_locked_lean_joint_is_the_whipple_browser_with_a_rigid_rider(speed):
    """Moore's generated leaning-rider equations with the lean joint locked against Meijaard's
    formulas for the same bicycle and rider (rear frame = legs + upper body: 33.044 + 48.816 =
    81.86 kg). The two rider inertias are separate Yeadon computations that agree to ~1e-5,
    hence 1e-4; the wheel Ixx swap alone moves them by 2e-3 of the largest entry or more."""
    a, b = lean.rigid_rider_state_space(speed)
    a_ref, b_ref = _rigid_browser_jason(speed)
    assert np.abs(a - a_ref).max() < 1e-4 * np.abs(a_ref).max()
    np.testing.assert_allclose(b, b_ref, atol=1e-5 * np.abs(b_ref).max())
    lam = np.sort_complex(np.linalg.eigvals(a))
    lam_ref = np.sort_complex(np.linalg.eigvals(a_ref))
    assert np.abs(lam - lam_ref).max() < 1e-4 * np.abs(lam_ref).max()


def test_heading_and_lateral_rows_are_the_whipple_kinematics():
    """psi' = cos(lam) (v steer + c steer') / w with the Browser's w, c, lam; yP' = v psi."""
    v = 4.0
    a, _ = lean.lean_state_space(v)
    g = params.steer_geometry("city")
    h, y = lean.LEAN_STATES.index("heading"), lean.LEAN_STATES.index("y_rear")
    cl = np.cos(g["lam"])
    assert a[h, 1] == pytest.approx(v * cl / g["w"], rel=1e-9)
    assert a[h, 4] == pytest.approx(g["c"] * cl / g["w"], rel=1e-9)
    assert a[y, h] == pytest.approx(v)
    assert np.count_nonzero(np.abs(a[h]) > 1e-12) == 2


def test_lean_plant_wires_the_filter_to_the_lean_torque():
    p = lean.lean_plant(5.0)
    a8, b8 = lean.lean_state_space(5.0)
    np.testing.assert_array_equal(p.A[:8, 8], b8[:, 2])  # filter torque = T9
    np.testing.assert_array_equal(p.B_f[:8], b8[:, :2])  # pedalling: T4, T7
    assert p.C[0, lean.LEAN_STATES.index("lean")] == 1.0  # innermost loop on the lean angle
    # static gain of the filter: one
    wn2 = -p.A[9, 8]
    assert p.B_u[9] / wn2 == pytest.approx(1.0)


def test_neuromuscular_pair_never_reaches_the_rule_damping_with_a_restoring_gain():
    """kDelta > 0 (restoring lean torque): the filter's pair only gains damping (0.707 at zero
    gain, the filter's own); the rule's 0.1289 is reached only with kDelta ~ -1e5 N m/rad
    (positive lean feedback), where the inner loop diverges at ~70 rad/s."""
    p = lean.lean_plant(5.0)
    scan = lean.inner_rule_scan(p)
    k = scan.k_delta_n_m_rad
    assert scan.nm_damping[k == 0][0] == pytest.approx(plant.NEURO_DAMPING, abs=1e-9)
    assert scan.nm_damping[k > 0].min() > 0.70
    k_rule = lean.rule_solution(p, scan)
    assert -2e5 < k_rule < -5e4
    # recomputed here: a pair of the closed inner loop has the rule's damping at that gain
    cl = p.A + np.outer(p.B_u, -k_rule * p.C[0])
    lam = np.linalg.eigvals(cl)
    lam = lam[lam.imag > 0]
    assert np.min(np.abs(-lam.real / np.abs(lam) - gains.ZETA_DELTA)) < 1e-8
    assert np.linalg.eigvals(cl).real.max() > 50.0


@pytest.mark.parametrize("speed", [2.5, 5.0, 7.0, 10.0])
def test_no_restoring_lean_gain_stabilises_the_inner_loop(speed):
    """A dense scan of kDelta 1-1e4 N m/rad, closed by hand: the lean loop alone is unstable
    at every gain (the free lean joint, k9 = c9 = 0, behind the filter's lag); the refined
    minimum of the largest real part agrees with the scan's."""
    p = lean.lean_plant(speed)
    dyn = list(lean.DYNAMIC)
    e = np.zeros(p.A.shape[0])
    e[lean.PLANT_STATES.index("lean")] = 1.0
    worst = min(np.linalg.eigvals((p.A - k * np.outer(p.B_u, e))[np.ix_(dyn, dyn)]).real.max()
                for k in np.geomspace(1.0, 1e4, 4001))
    assert worst > 0.05
    k_best, re_best = lean.best_restoring_gain(p, lean.inner_rule_scan(p))
    assert 0 < re_best <= worst + 1e-9 and worst - re_best < 0.05
    assert 50.0 < k_best < 300.0


def test_rules_continued_from_the_formal_solution_hold_and_are_unstable():
    """The rules' other targets (0.0855 damping, crossovers 2/1/0.5 rad/s) hold for the gains
    :func:`lean.full_rules_from` returns, and the fully closed loop is unstable."""
    p = lean.lean_plant(5.0)
    k_rule = lean.rule_solution(p, lean.inner_rule_scan(p))
    k, re = lean.full_rules_from(p, k_rule)
    assert k[0] == pytest.approx(k_rule, rel=1e-8)
    lam = np.linalg.eigvals(plant.closed_matrix(p, k, 2))
    lam = lam[lam.imag > 0]
    assert np.min(np.abs(-lam.real / np.abs(lam) - gains.ZETA_PHIDOT)) < 1e-8
    for loop, wc in zip((2, 3, 4), gains.CROSSOVER_RAD_S, strict=True):
        assert k[loop] * abs(plant.open_loop_response(p, k, loop, [wc])[0]) == pytest.approx(1.0)
    assert re == pytest.approx(np.linalg.eigvals(plant.closed_matrix(p, k)).real.max())
    assert re > 1.0


def test_lean_rider_table_has_units_in_its_columns_and_one_row_per_speed():
    t = lean.lean_rider_table(np.array([5.0, 10.0]))
    assert list(t.columns) == list(lean.LEAN_TABLE_COLUMNS)
    assert t.speed_m_s.tolist() == [5.0, 10.0]
    assert not t.closed_loop_stable.any()
    assert (t.open_loop_max_real_rad_s > 5.0).all()  # the upper body falls (~7 rad/s)
