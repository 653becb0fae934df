"""Seat changes of the rigid city rider, and the parameters of the derived models.

Expected values: the benchmark roll inertia formula (Meijaard 2007, T_xx) for the seat change of
the rigid city rider. HS and CF have their own arm loops (tests/nonlinear/test_arms.py,
tests/nonlinear/test_calibration.py).
"""

from __future__ import annotations

import pytest

from pedalrepro import params
from pedalrepro.nonlinear import bodies, codegen, symbolic
from pedalrepro.nonlinear.nonlinear_model import (
    NonlinearModel,
    benchmark_matrices,
    moore_parameters,
)


@pytest.mark.parametrize("options", [symbolic.ModelOptions(), symbolic.ModelOptions(arms=True)])
def test_derived_model_parameters_are_bodies_only(options):
    """Every parameter of a derived model is a body parameter: the bicycle's (Moore's
    parametrisation), the arm loops' (symbolic.ARM_PARAMETERS) and gravity. The retired
    linear-correction terms (16 ``lc_*`` parameters that nothing set) are not derived."""
    names = set(codegen.load(options).PARAMS)
    # the values the numeric side supplies (benchmark -> Moore 2012 conversion, and g)
    bicycle = set(moore_parameters(params.benchmark_parameters("benchmark")))
    arms = set(symbolic.ARM_PARAMETERS) if options.arms else set()
    assert names == bicycle | arms


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
