"""Periodic orbits at hostile torque scales (issue 22, case 5).

A zero torque scale is the upright straight-ahead motion: zero amplitude, and Floquet
multipliers exp(lambda T) of the model's own linearisation at that speed (the monodromy of an
equilibrium). A tiny scale (1e-300) is the same orbit scaled: amplitudes proportional to the
scale. Tolerances: the multipliers are eigenvalues of a monodromy computed with forward
differences (~1e-8 of the spectral radius, tests/periodic/test_periodic.py), checked at 1e-6; the
amplitudes per unit scale of a directly solved 1e-5 orbit differ from the linear limit by the
non-linear terms, O(1e-5^2) relative, and the integration's ~1e-9: checked at 1e-6. Before the
fix, scale 0 gave |mu| 16.3 at HR 5 m/s (unstable; the upright motion is stable there) and NaN
or inf ended in a ZeroDivisionError traceback.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from pedalrepro import linear, periodic

OMEGA = 2 * np.pi
SPEED = 5.0


def _match(mu_orbit: np.ndarray, mu_linear: np.ndarray) -> float:
    return float(max(np.min(np.abs(mu_orbit - m)) for m in mu_linear)
                 / np.max(np.abs(mu_linear)))


@pytest.mark.parametrize("scale", [0.0, 1e-300, -1e-300, 1e-9])
def test_zero_or_tiny_torque_gives_the_upright_multipliers(scale):
    s = periodic.OrbitSolver("HR", "NT", OMEGA, torque_scale=scale)
    orb = s.solve(SPEED)
    assert orb.converged and orb.torque_scale == scale
    lam = linear.eigenvalues(s.linear, SPEED)
    assert _match(orb.floquet_multipliers, np.exp(lam * s.period_s)) < 1e-6
    assert orb.stable and np.max(np.abs(orb.floquet_multipliers)) < 0.75
    direct = periodic.OrbitSolver("HR", "NT", OMEGA, torque_scale=1e-5).solve(SPEED)
    assert direct.converged
    per_unit = direct.roll_amplitude_rad / 1e-5
    if scale == 0.0:
        assert orb.roll_amplitude_rad == 0.0 and orb.steer_amplitude_rad == 0.0
        assert np.all(orb.nodes == 0.0) and orb.periodicity_residual == 0.0
    else:
        assert orb.roll_amplitude_rad / abs(scale) == pytest.approx(per_unit, rel=1e-6)
        assert orb.steer_amplitude_rad / abs(scale) == pytest.approx(
            direct.steer_amplitude_rad / 1e-5, rel=1e-6)
        phase = direct.roll_phase_rad + (np.pi if scale < 0 else 0.0)
        assert np.exp(1j * orb.roll_phase_rad) == pytest.approx(np.exp(1j * phase), abs=1e-6)


@pytest.mark.parametrize("value", [float("nan"), float("inf"), float("-inf")])
def test_non_finite_torque_scale_is_refused(value):
    with pytest.raises(ValueError, match="torque_scale must be finite"):
        periodic.OrbitSolver("HR", "NT", OMEGA, torque_scale=value)


@pytest.mark.parametrize("argv, word", [
    (["--torque-scale", "nan"], "--torque-scale must be finite"),
    (["--torque-scale", "inf"], "--torque-scale must be finite"),
    (["--speed-m-s", "nan"], "--speed-m-s must be finite"),
    (["--cadence-rpm", "nan"], "--cadence-rpm must be finite"),
])
def test_cli_refuses_non_finite_values(capsys, argv, word):
    from pedalrepro.cli import main

    base = {"--model": "HR", "--speed-m-s": "5", "--cadence-rpm": "60"}
    base.update(dict(zip(argv[::2], argv[1::2], strict=True)))
    assert main(["periodic"] + [x for kv in base.items() for x in kv]) == 2
    err = capsys.readouterr().err
    assert word in err and "Traceback" not in err


def test_cli_zero_torque_scale_is_the_stable_upright_motion(capsys):
    from pedalrepro.cli import main

    assert main(["periodic", "--model", "HR", "--speed-m-s", "5", "--cadence-rpm", "60",
                 "--torque-scale", "0"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["stable"] is True and out["roll_amplitude_rad"] == 0.0
    assert max(out["floquet_multipliers_abs"]) < 0.75
