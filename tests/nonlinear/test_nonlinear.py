"""Checks of the non-linear Whipple model: linearisation against Meijaard et al. (2007), energy."""

from __future__ import annotations

import numpy as np
import pytest
import yaml
from required import CC, skip_unless_required

from pedalrepro import params, paths
from pedalrepro.nonlinear import codegen, symbolic
from pedalrepro.nonlinear.nonlinear_model import NonlinearModel, benchmark_matrices
from pedalrepro.nonlinear.simulate import simulate


@pytest.fixture(scope="module")
def benchmark_model() -> NonlinearModel:
    return NonlinearModel(params.benchmark_parameters("benchmark"))


def test_linearisation_equals_meijaard_2007(benchmark_model):
    """M, C1, K0, K2 of the linearised non-linear model equal the published benchmark matrices.

    The published matrices carry 14 significant digits; the complex-step Jacobian is exact to
    rounding, so both an absolute (the zero entries) and a relative 1e-9 tolerance hold.
    """
    published = yaml.safe_load((paths.PUBLISHED / "meijaard2007.yaml").read_text())
    ours = benchmark_matrices(benchmark_model)
    for name in ("M", "C1", "K0", "K2"):
        np.testing.assert_allclose(ours[name], np.array(published[name]), rtol=1e-9, atol=1e-9,
                                   err_msg=name)


def test_linearisation_independent_of_speed_pair(benchmark_model):
    """C1, K0, K2 from speeds (0, 1) and (2, 7) agree: K(v) is quadratic and C(v) linear in v."""
    a = benchmark_matrices(benchmark_model, (0.0, 1.0))
    b = benchmark_matrices(benchmark_model, (2.0, 7.0))
    for name in ("M", "C1", "K0", "K2"):
        np.testing.assert_allclose(a[name], b[name], rtol=1e-9, atol=1e-9, err_msg=name)


def test_energy_is_conserved(benchmark_model):
    """No dissipation, rolling without slip: total energy constant over 15 s (rtol 1e-10)."""
    nl = benchmark_model
    x0 = nl.upright_state(5.0, roll_rate_rad_s=0.5)
    sim = simulate(nl, 5.0, 15.0, 20.0, x0=x0, rtol=1e-10, atol=1e-10, method="DOP853",
                   fall_roll_rad=1.0)
    assert not sim.fell
    drift, _ = nl.energy_drift(sim.t_s, sim.states)
    assert drift < 1e-7
    # and the motion is not trivial: the roll rate changed and the kinetic energy moved around
    assert np.ptp(sim.states[3]) > 0.1


def test_stable_speed_decays_unstable_speed_grows(benchmark_model):
    """At 5 m/s (inside 4.29-6.02 m/s) a roll-rate perturbation decays; at 2 m/s it falls."""
    nl = benchmark_model
    stable = simulate(nl, 5.0, 20.0, 10.0, x0=nl.upright_state(5.0, 0.2))
    assert not stable.fell
    assert np.max(np.abs(stable.roll_rad[-20:])) < 0.05 * np.max(np.abs(stable.roll_rad))
    unstable = simulate(nl, 2.0, 20.0, 10.0, x0=nl.upright_state(2.0, 0.2), fall_roll_rad=1.0)
    assert unstable.fell and unstable.t_end_s < 20.0


def test_derivation_is_cached(benchmark_model, monkeypatch):
    """A second load reads the generated module: derive() is never called again."""
    path = codegen.generated_source(symbolic.ModelOptions())
    assert path.exists()

    def boom(*args, **kwargs):
        raise AssertionError("re-derived although cached")

    monkeypatch.setattr(symbolic, "derive", boom)
    assert codegen.generated_source(symbolic.ModelOptions()) == path


def test_hand_written_c_change_recompiles_without_re_deriving(benchmark_model, monkeypatch,
                                                             tmp_path):
    """Editing a shared header of the hand-written C (pedalrepro/csrc) changes the library, never
    the derivation key: the library is rebuilt from the cached generated C (derive() is not
    called)."""
    import shutil

    from pedalrepro.integrator import build
    from pedalrepro.nonlinear import library

    options = symbolic.ModelOptions()
    key, so = codegen.cache_key(options), library.compiled_library(options)
    if so is None:
        skip_unless_required(CC, "no C compiler")
    edited = tmp_path / "csrc"
    shutil.copytree(build.CSRC, edited)
    (edited / "lu.h").write_text((edited / "lu.h").read_text() + "\n/* an edit */\n")

    def boom(*args, **kwargs):
        raise AssertionError("re-derived although only hand-written C changed")

    monkeypatch.setattr(symbolic, "derive", boom)
    rebuilt = library.compiled_library(options, csrc=edited)
    assert codegen.cache_key(options) == key
    assert rebuilt != so and rebuilt.exists() and rebuilt.name.startswith(key)
    rebuilt.unlink()


@pytest.mark.parametrize(("name", "options", "steer"), [
    ("HR", symbolic.ModelOptions(legs=True), 0.05),             # moving legs
    ("CF", symbolic.ModelOptions(legs=True, arms=True), 0.15),  # + CF's arm loops
    ("HS", symbolic.ModelOptions(legs=True, arms=True), 0.15),  # + HS's arms (free plane)
])
def test_compiled_rhs_equals_generated_python(name, options, steer):
    """C right-hand side = generated Python to rounding (NP models, off-equilibrium state)."""
    from pedalrepro.nonlinear import models

    nl = models.np_model(name, 2.0 * np.pi)
    assert nl.options == options
    if nl.lib is None:
        skip_unless_required(CC, "no C compiler: only the Python path exists")
    x = np.array([0.1, nl.nominal_pitch_rad, steer, 0.3, -12.0, -0.2])
    np.testing.assert_allclose(nl.rhs(0.3, x, (1.0, 0.2)), nl.rhs_python(0.3, x, (1.0, 0.2)),
                               rtol=1e-10, atol=1e-12)


def test_moving_legs_remove_exactly_the_frozen_legs():
    """NP's body B plus the six bodies at crank angle 0 (the prescribed motion at t = 0)
    restores the calibrated NT body exactly (issue 11 part 6)."""
    from pedalrepro.nonlinear import bodies, rigid

    _, spec, frozen = bodies.leg_bodies("CR", 2.0 * np.pi)
    rest = bodies.without_legs("CR")
    full = bodies.legs_fixed("CR")
    back = rigid.combine([rigid.body_part(rest, "B")] + list(frozen))
    m, com, inertia = back.mass, back.com, back.inertia
    assert m == pytest.approx(full["mB"], rel=1e-12)
    assert com[0] == pytest.approx(full["xB"], abs=1e-12)
    assert com[2] == pytest.approx(full["zB"], abs=1e-12)
    assert inertia[0, 0] == pytest.approx(full["IBxx"], rel=1e-12)
    assert inertia[0, 2] == pytest.approx(full["IBxz"], rel=1e-10)
    # the frozen bodies are where the prescribed motion puts them at t = 0 (rear-frame x, z)
    lam, r_r = full["lam"], full["rR"]
    s0 = spec(0.0)
    for k, part in enumerate(frozen):
        dx, dz = part.com[0], part.com[2] + r_r
        assert s0[3 * k] == pytest.approx(dx * np.cos(lam) - dz * np.sin(lam), abs=1e-9)
        assert s0[3 * k + 1] == pytest.approx(dx * np.sin(lam) + dz * np.cos(lam), abs=1e-9)


def test_leg_fourier_series_reproduces_the_four_bar():
    """The prescribed leg motion (32-harmonic series) equals pedalrepro.legs at odd times."""
    from pedalrepro import legs
    from pedalrepro.nonlinear import bodies

    w = 7.0
    _, spec, _ = bodies.leg_bodies("CR", w)
    geom = legs.leg_geometry("city", "O")
    t = np.array([0.0123, 0.4567, 0.8])
    motion = legs.leg_motion(geom, w, t)
    lam = bodies.bicycle_rider("CR")["lam"]
    s = np.array([spec(ti) for ti in t])
    k = symbolic.LEG_BODIES.index("shank_r")
    # the shank angle in the rear frame is the four-bar pitch angle minus the steer-axis tilt
    np.testing.assert_allclose(s[:, 3 * k + 2], motion.pitch_rad["shank"] - lam, atol=1e-9)
    np.testing.assert_allclose(s[:, 18 + 3 * k + 2], motion.pitch_rate_rad_s["shank"], atol=1e-7)
    np.testing.assert_allclose(s[:, 36 + 3 * k + 2], motion.pitch_acc_rad_s2["shank"], rtol=1e-6,
                               atol=1e-5)
