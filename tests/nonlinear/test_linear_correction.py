"""The optional linear correction terms of the non-linear model, and seat changes.

Expected values: Meijaard et al. (2007) plus an arbitrary correction for the correction terms,
and the benchmark roll inertia formula (Meijaard 2007, T_xx) for the seat change of the rigid
city rider. HS and CF have their own arm loops (tests/nonlinear/test_arms.py,
tests/nonlinear/test_calibration.py).
"""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import params
from pedalrepro.nonlinear import bodies, models, symbolic
from pedalrepro.nonlinear.nonlinear_model import NonlinearModel, benchmark_matrices

NAMES = ("M", "C1", "K0", "K2")


def assert_matrices_equal(got, want, rel=1e-9, abs_=1e-9):
    for k in NAMES:
        np.testing.assert_allclose(got[k], want[k], rtol=rel, atol=abs_, err_msg=k)


def test_correction_adds_exactly_to_the_benchmark():
    """Arbitrary correction on the benchmark bicycle: linearisation = Meijaard 2007 + correction."""
    rng = np.random.default_rng(7)
    corr = {k: rng.normal(scale=0.3, size=(2, 2)) for k in NAMES}
    corr["M"] = corr["M"] @ corr["M"].T * 0.1  # keep the mass matrix positive definite
    bench = params.benchmark_parameters("benchmark")
    plain = benchmark_matrices(NonlinearModel(bench))
    corrected = benchmark_matrices(NonlinearModel(bench, linear_correction=corr))
    assert_matrices_equal(corrected, {k: plain[k] + corr[k] for k in NAMES})


def test_correction_parameters_are_the_sixteen_entries():
    """The optional linear correction (NonlinearModel(linear_correction=...), zero in every
    thesis model since HS has its own arm loops) has one parameter per matrix entry."""
    assert set(symbolic.correction_parameter_names()) == {
        f"lc_{k}_{i}{j}" for k in NAMES for i in range(2) for j in range(2)}
    assert not any(v != 0.0 for n, v in zip(models.nt_model("HR")._code.PARAMS,
                                           models.nt_model("HR").p, strict=True)
                   if n.startswith("lc_"))


@pytest.mark.parametrize("bad", [{"M": np.eye(2)}, {k: np.eye(3) for k in NAMES},
                                 {k: np.full((2, 2), np.nan) for k in NAMES}])
def test_bad_correction_is_a_clear_error(bad):
    with pytest.raises((KeyError, ValueError), match="linear correction"):
        NonlinearModel(params.benchmark_parameters("benchmark"), linear_correction=bad)


def test_original_seat_changes_roll_inertia_as_the_benchmark_formula_says():
    """Rigid city rider raised 0.05 m: M[0,0] changes by d(I_Bxx + m_B z_B^2) (Meijaard T_xx)."""
    low, high = bodies.bicycle_rider("CR"), bodies.bicycle_rider("CR", original_seat=True)
    assert high["mB"] == pytest.approx(low["mB"], rel=1e-14)
    assert high["zB"] < low["zB"]  # z down: the rider is higher on the original seat
    expected = (high["IBxx"] + high["mB"] * high["zB"] ** 2) - (low["IBxx"]
                                                                 + low["mB"] * low["zB"] ** 2)
    lo, hi = (benchmark_matrices(NonlinearModel(b)) for b in (low, high))
    assert hi["M"][0, 0] - lo["M"][0, 0] == pytest.approx(expected, rel=1e-9)
    # gravity stiffness changes by -m_B dz_B (Meijaard 2007 K0[0,0] = m_t z_t)
    assert hi["K0"][0, 0] - lo["K0"][0, 0] == pytest.approx(
        high["mB"] * high["zB"] - low["mB"] * low["zB"], rel=1e-9)
