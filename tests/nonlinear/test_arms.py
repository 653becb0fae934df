"""The arm loops of model CF (thesis Sec 3.1.1.2-3.1.1.3, Fig 3.4; pedalrepro.nonlinear.arms).

Expected values come from physics and independent calculations: the Yeadon posture of
BicycleParameters (the loop must close on it), mass bookkeeping done by a second route, the
kinetic energy of the arm particles from finite differences of the closed-form positions
(independent of Kane's method), energy conservation and the generated Python code.
"""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro.nonlinear import arms, bodies, models, rigid
from pedalrepro.nonlinear.nonlinear_model import NonlinearModel, benchmark_matrices
from pedalrepro.nonlinear.settings import model_options
from pedalrepro.nonlinear.simulate import simulate

NAMES = ("M", "C1", "K0", "K2")
MOVING = ("arm_m_elbow", "arm_m_upper", "arm_m_fore")


def test_nominal_posture_closes_the_loop():
    """At the original seat and zero steer the closed-form elbow is Yeadon's elbow (1e-6 m).

    The sagittal-plane shoulder (flexion axis = trunk lateral axis) cannot close this loop: the
    Yeadon arm is nearly straight and its elbow is out of the shoulder's sagittal plane.
    """
    nominal = arms.nominal_posture()
    assert nominal["elbow_distance_m"] < 1e-6
    assert nominal["sagittal_gap_m"] > 0.0
    assert nominal["elbow_lateral_offset_m"] == pytest.approx(0.047, abs=1e-3)


@pytest.mark.parametrize("original_seat", [False, True])
def test_closed_form_keeps_the_loop_closed_at_any_steer(original_seat):
    """|E - S| = a, |E - H(delta)| = b and E in the shoulder's flexion plane (1e-12 m) for
    steer angles within the arms' reach, both arms; beyond it the loop cannot close (NaN).

    Reach: 0.41 rad at the 0.72 m seat; 0.046 rad at 0.77 m, where Yeadon's arm is nearly
    straight (elbow 14 deg).
    """
    loop = bodies.arm_loop("CF", original_seat)
    bench = bodies.model_bodies("CF", original_seat)[0]
    reach = arms.steer_reach_rad(loop, bench)
    for arm in (loop, loop.mirrored()):
        for delta in reach * np.array([-0.999, -0.5, 0.0, 0.3, 0.999]):
            h = arms.grip_at_steer(arm.grip, delta, bench)
            e = arm.elbow(h)
            assert np.linalg.norm(e - arm.shoulder) == pytest.approx(arm.a, abs=1e-12)
            assert np.linalg.norm(h - e) == pytest.approx(arm.b, abs=1e-12)
            assert arm.normal @ (e - arm.shoulder) == pytest.approx(0.0, abs=1e-12)
    with np.errstate(invalid="ignore"):
        beyond = loop.elbow(arms.grip_at_steer(loop.grip, -1.01 * reach, bench))
        beyond_l = loop.mirrored().elbow(arms.grip_at_steer(loop.mirrored().grip, 1.01 * reach,
                                                            bench))
    assert not (np.all(np.isfinite(beyond)) and np.all(np.isfinite(beyond_l)))
    # at the reach one arm is fully stretched: projected shoulder-grip distance = a + b'
    stretch = []
    for arm in (loop, loop.mirrored()):
        for sgn in (1.0, -1.0):
            r = arms.grip_at_steer(arm.grip, sgn * reach, bench) - arm.shoulder
            dy = arm.normal @ r
            stretch.append(np.linalg.norm(r - dy * arm.normal) - arm.a - np.sqrt(arm.b**2 - dy**2))
    assert max(stretch) == pytest.approx(0.0, abs=1e-9)
    assert reach > (0.02 if original_seat else 0.3)


def test_runs_end_at_the_arms_reach():
    """A CF run that steers beyond the arms' reach ends like a fall at the steer limit, in the
    compiled and in the solve_ivp integrator, instead of failing on a non-finite state."""
    nl = models.nt_model("CF")
    reach = arms.steer_reach_rad(bodies.arm_loop("CF"), bodies.model_bodies("CF")[0])
    assert nl.steer_limit_rad == pytest.approx(0.95 * reach, rel=1e-12)
    x0 = nl.upright_state(1.0, steer_rate_rad_s=3.0)
    for sim in (simulate(nl, 1.0, 5.0, 100.0, x0=x0, compiled=False),
                simulate(nl, 1.0, 5.0, 100.0, x0=x0)):
        assert sim.fell and sim.t_end_s < 5.0
        last = np.flatnonzero(np.isfinite(sim.steer_rad))[-1]
        assert abs(sim.steer_rad[last]) <= nl.steer_limit_rad + 1e-9
        assert abs(sim.roll_rad[last]) < 1.0


def test_rod_particles_reproduce_the_segment():
    """Three particles: Yeadon mass, COM on the axis and transverse central inertia."""
    y = arms.yeadon_arms()
    for part, start, end in ((y.upper, y.shoulder, y.elbow), (y.forearm, y.elbow, y.grip)):
        m1, m2, m3, c = arms.rod_particles(part, start, end)
        assert min(m1, m2, m3) > 0
        assert m1 + m2 + m3 == pytest.approx(part.mass, rel=1e-14)
        pts = [start, end, start + c * (end - start)]
        com = (m1 * pts[0] + m2 * pts[1] + m3 * pts[2]) / part.mass
        np.testing.assert_allclose(com, part.com, atol=1e-12)
        e = (end - start) / np.linalg.norm(end - start)
        i_perp = sum(m * ((p - com) @ e) ** 2
                     for m, p in zip((m1, m2, m3), pts, strict=True))
        i_axial = e @ part.inertia @ e
        assert i_perp == pytest.approx((np.trace(part.inertia) - i_axial) / 2, rel=1e-12)


def _zero_arm_masses(bench: dict, arm_values: dict, loop) -> tuple[dict, dict]:
    """Route A: the arm model's bodies with the shoulder/grip particles taken back out."""
    rear, front = arms.fixed_parts(loop)
    b = rigid.with_body(bench, "B", rigid.subtract(rigid.body_part(bench, "B"), rear))
    b = rigid.with_body(b, "H", rigid.subtract(rigid.body_part(b, "H"), front))
    return b, dict(arm_values) | dict.fromkeys(MOVING, 0.0)


def test_massless_arms_equal_the_plain_whipple_model():
    """Arm masses zero (moving particles massless, shoulder/grip particles taken out of the
    frames): the arm model linearises (1e-9) to the plain Whipple model of the same bodies,
    and the plain model's body B is the assembly's rear frame + rider without arms + frozen
    legs (mass bookkeeping by a second route)."""
    bench, values = bodies.model_bodies("CF")
    loop = bodies.arm_loop("CF")
    a_bench, a_values = _zero_arm_masses(bench, values, loop)
    route_a = benchmark_matrices(NonlinearModel(a_bench, model_options("CF"),
                                                arm_parameters=a_values))
    route_b = benchmark_matrices(NonlinearModel(a_bench))
    for k in NAMES:
        np.testing.assert_allclose(route_a[k], route_b[k], rtol=1e-9, atol=1e-9, err_msg=k)
    asm, frames = bodies.model_assembly("CF")
    rest = [p for p in asm.rear_parts if p.inertia.any()]  # shoulder particles: no inertia
    m = frames["B"].mass + sum(p.mass for p in rest)
    assert a_bench["mB"] == pytest.approx(m, rel=1e-12)
    assert sum(p.mass for p in asm.frozen) == pytest.approx(2 * (0.2 + 4.392 + 7.2), rel=1e-12)


def test_arm_mass_matrix_from_finite_differences_of_the_loop():
    """M(CF) - M(CF, moving arm particles massless) = sum m J^T J over the six moving particles.

    J = [dr/dphi, dr/ddelta]: at zero speed a roll rate turns everything about the ground line
    (e_x x r), a steer rate moves the particles along the closed-form loop (central finite
    differences of :func:`arms.moving_particles`, independent of Kane's method) and yaws the
    rear frame about the rear contact at psi' = c cos(lam) / w delta' (trail; Meijaard et al.
    2007). Tolerance 1e-6 relative: finite-difference error ~ (1e-5)^2.
    """
    bench, values = bodies.model_bodies("CF")
    loop = bodies.arm_loop("CF")
    opts = model_options("CF")
    full = benchmark_matrices(NonlinearModel(bench, opts, arm_parameters=values))["M"]
    massless = dict(values) | dict.fromkeys(MOVING, 0.0)
    none = benchmark_matrices(NonlinearModel(bench, opts, arm_parameters=massless))["M"]
    h = 1e-5
    plus = arms.moving_particles(loop, h, bench)
    minus = arms.moving_particles(loop, -h, bench)
    k_yaw = bench["c"] * np.cos(bench["lam"]) / bench["w"]
    expected = np.zeros((2, 2))
    for (m, r), (_, rp), (_, rm) in zip(arms.moving_particles(loop, 0.0, bench), plus, minus,
                                        strict=True):
        j = np.column_stack([np.cross([1.0, 0, 0], r),
                             (rp - rm) / (2 * h) + k_yaw * np.cross([0, 0, 1.0], r)])
        expected += m * j.T @ j
    np.testing.assert_allclose(full - none, expected, rtol=1e-6, atol=1e-9 * expected[1, 1])
    assert expected[1, 1] > 0.1 * full[1, 1]  # the arms add a large share of the steer inertia


def test_energy_is_conserved_with_arms():
    """Unforced CF (legs fixed, arm loops moving with the steer): total energy, which includes
    the arm particles, is constant over 10 s (no dissipation, scleronomic constraints).

    CF's capsize root is unstable at every speed (Appendix B: 0.34 1/s at 10 m/s), so a
    steer-rate perturbation at 10 m/s grows into a large lean within the 10 s without
    falling. DOP853 at rtol = atol = 1e-10: the drift stays below 1e-9.
    """
    nl = models.nt_model("CF")
    x0 = nl.upright_state(10.0, steer_rate_rad_s=0.3)
    sim = simulate(nl, 10.0, 10.0, 20.0, x0=x0, rtol=1e-10, atol=1e-10, method="DOP853",
                   fall_roll_rad=1.0)
    assert not sim.fell
    drift, _ = nl.energy_drift(sim.t_s, sim.states)
    assert drift < 1e-9
    assert np.max(np.abs(sim.roll_rad)) > 0.3  # far from the linear range
    assert np.ptp(sim.states[2]) > 0.05  # the steer (and so the arms) moved


def test_energy_expression_includes_the_arms():
    """Energy of the arm model minus that with massless moving particles = their KE + PE."""
    bench, values = bodies.model_bodies("CF")
    loop = bodies.arm_loop("CF")
    opts = model_options("CF")
    with_arms = NonlinearModel(bench, opts, arm_parameters=values)
    without = NonlinearModel(bench, opts, arm_parameters=dict(values) | dict.fromkeys(MOVING, 0.0))
    x = with_arms.upright_state(0.0, steer_rate_rad_s=1.0)
    h = 1e-6
    k_yaw = bench["c"] * np.cos(bench["lam"]) / bench["w"]
    ke = pe = 0.0
    for (m, r), (_, rp), (_, rm) in zip(arms.moving_particles(loop, 0.0, bench),
                                        arms.moving_particles(loop, h, bench),
                                        arms.moving_particles(loop, -h, bench), strict=True):
        v = (rp - rm) / (2 * h) + k_yaw * np.cross([0, 0, 1.0], r)
        ke += 0.5 * m * v @ v
        pe += -m * bench["g"] * r[2]  # z down
    diff = with_arms.energy_J(0.0, x) - without.energy_J(0.0, x)
    assert diff == pytest.approx(ke + pe, rel=1e-8)


def test_original_seat_model_is_the_own_cf_model_unlowered():
    """Fig E.1 model: CF's own linearisation with the rider not lowered (hands on the bar)."""
    cf77 = models.original_seat_model("CF")
    want = benchmark_matrices(models.nt_model("CF", original_seat=True))
    for k in NAMES:
        np.testing.assert_allclose(getattr(cf77, k), want[k], rtol=1e-12, err_msg=k)
    low, high = bodies.arm_loop("CF"), bodies.arm_loop("CF", original_seat=True)
    # the shoulders are 0.05 m higher along the seat tube; the grip does not move
    assert np.linalg.norm(high.shoulder - low.shoulder) == pytest.approx(0.05, rel=1e-12)
    np.testing.assert_array_equal(high.grip, low.grip)
    # more extended elbow at the higher seat: the shoulder-grip distance grows
    assert np.linalg.norm(high.grip - high.shoulder) > np.linalg.norm(low.grip - low.shoulder)


def test_original_seat_only_for_the_city_bicycle():
    with pytest.raises(ValueError, match="city bicycle"):
        models.original_seat_model("HS")
