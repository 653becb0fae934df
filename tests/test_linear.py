"""Linear models and eigen analysis (Sec 3.1.1, 3.2.1, Appendix B; Meijaard et al. 2007)."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import linear, params, paths

SPEEDS = np.arange(0.0, 10.0 + 1e-9, 0.01)


@pytest.fixture(scope="module")
def meijaard() -> dict:
    return params.read_yaml(paths.PUBLISHED / "meijaard2007.yaml")


@pytest.fixture(scope="module")
def summaries() -> dict:
    return {n: linear.summarise(linear.linear_model(n), SPEEDS) for n in linear.MODEL_NAMES}


def test_benchmark_matrices_match_meijaard_2007(meijaard):
    model = linear.linear_model("benchmark")
    for key in ("M", "C1", "K0", "K2"):
        np.testing.assert_allclose(getattr(model, key), np.array(meijaard[key]), rtol=1e-12,
                                   atol=1e-12, err_msg=key)


def test_benchmark_weave_and_capsize_speeds(meijaard, summaries):
    s = summaries["benchmark"]
    assert s.weave_speed_m_s == pytest.approx(meijaard["weave_speed_m_s"], abs=1e-3)
    assert s.capsize_speed_m_s == pytest.approx(meijaard["capsize_speed_m_s"], abs=1e-3)
    # much better than asked: root finding, not grid reading
    assert s.weave_speed_m_s == pytest.approx(meijaard["weave_speed_m_s"], abs=1e-6)
    assert (s.stable_from_m_s, s.stable_to_m_s) == pytest.approx(
        (s.weave_speed_m_s, s.capsize_speed_m_s), abs=1e-9)


@pytest.mark.parametrize("name, lo, hi", [("HS", 6.02, 9.45), ("HR", 4.76, 7.78),
                                           ("CR", 5.05, 7.25)])
def test_appendix_b_self_stable_ranges(summaries, name, lo, hi):
    s = summaries[name]
    assert s.stable_from_m_s == pytest.approx(lo, abs=0.005)
    assert s.stable_to_m_s == pytest.approx(hi, abs=0.005)
    assert s.weave_speed_m_s == pytest.approx(lo, abs=0.005)
    assert s.capsize_speed_m_s == pytest.approx(hi, abs=0.005)


def test_cf_has_no_stable_range_and_its_weave_branch_stabilises_at_3_21(summaries):
    """DESIGN.md / errata 16: the 3.2 m/s crossing is a real root of the weave branch."""
    s = summaries["CF"]
    assert s.stable_from_m_s is None and s.stable_to_m_s is None
    assert s.capsize_speed_m_s is None
    assert s.weave_speed_m_s == pytest.approx(3.21, abs=0.005)
    assert s.weave_frequency_at_weave_speed_rad_s is None  # still a real root there
    model = linear.linear_model("CF")
    sweep = linear.eigen_sweep(model, SPEEDS)
    assert np.all(sweep.branch("capsize").real > 0)  # capsize root positive at every speed
    onset = linear.oscillatory_onset(model, sweep)
    assert 3.6 < onset < 3.9  # joins another real root into the oscillatory weave near 3.7
    e = linear.eigenvalues(model, s.weave_speed_m_s)
    assert np.min(np.abs(e)) < 1e-8  # the root crossing zero is real (lambda = 0 exactly)


def test_benchmark_weave_frequency_matches_fig_g7_resonance(summaries):
    # Fig G.7: the resonance sits at the weave speed with the cadence = Im(weave) = 3.43 rad/s
    assert summaries["benchmark"].weave_frequency_at_weave_speed_rad_s == pytest.approx(
        3.43, abs=0.01)


def test_mode_names_at_high_speed():
    sweep = linear.eigen_sweep(linear.linear_model("benchmark"), SPEEDS)
    last = dict(zip(sweep.names, sweep.eigenvalues[-1], strict=True))
    assert abs(last["weave"].imag) > 5  # oscillatory
    assert last["caster"].real < -10  # strongly negative
    assert 0 < last["capsize"].real < 0.5  # slightly unstable at 10 m/s (Fig 3.6)
    # branches are continuous: no jump larger than the eigenvalue change over one step
    jumps = np.abs(np.diff(sweep.eigenvalues, axis=0)).max()
    assert jumps < 1.0


def test_state_matrix_reproduces_second_order_form():
    # Physics: x = [q, q'] with q'' = -M^-1 (v C1 q' + (g K0 + v^2 K2) q)
    model = linear.linear_model("HS")
    v = 4.0
    a = linear.state_matrix(model, v)
    x = np.array([0.1, -0.2, 0.3, 0.05])
    qdd = -np.linalg.solve(model.M, v * model.C1 @ x[2:] + (model.g * model.K0
                                                             + v**2 * model.K2) @ x[:2])
    np.testing.assert_allclose(a @ x, np.r_[x[2:], qdd], rtol=1e-13)


def test_unknown_model_is_a_clear_error():
    with pytest.raises(KeyError, match="unknown linear model"):
        linear.linear_model("XX")
