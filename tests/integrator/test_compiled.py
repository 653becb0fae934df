"""The one home of the compiled code (pedalrepro/csrc, issue 24).

The Dormand-Prince tableau and the LU are written once; the simulation library and the
periodic-orbit library are composed from the same headers; the orbits' held-wheel-rate
right-hand side equals the simulation's right-hand side with the holding hub torque applied.
Tolerance 1e-12: both solve the same reduced Kane equations (model_rhs.h), the simulation its
3 x 3 system, the orbits the 2 x 2 system of the roll and steer rows with the rear-wheel
acceleration known to be zero; rounding of those solves is ~1e-15 of the accelerations (order 1
to 100 rad/s^2 here), so 1e-12 holds with margin and fails for any error in the elimination (a
wrong row or sign changes the accelerations by O(1)).
"""

from __future__ import annotations

import ctypes
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from required import CC, skip_unless_required

from pedalrepro import periodic
from pedalrepro.integrator import build

SRC = build.CSRC.parent  # src/pedalrepro


def _c_sources() -> dict[Path, str]:
    return {p: p.read_text() for p in SRC.rglob("*") if p.suffix in (".c", ".h")}


def test_tableau_lu_and_forcing_have_one_home():
    """A Dormand-Prince coefficient, the LU and the forcing each appear in one C file, the
    forcing struct is filled by one Python function."""
    texts = _c_sources()
    assert {p.name for p, t in texts.items() if "19372.0 / 6561" in t} == {"dopri.h"}
    assert {p.name for p, t in texts.items() if "static int lu_factor(" in t} == {"lu.h"}
    assert {p.name for p, t in texts.items() if "typedef struct" in t and "roll_re" in t} \
        == {"forcing.h"}
    assert {p.name for p, t in texts.items() if re.search(r"\bpedal_forcing\s*\(\s*const", t)} \
        == {"forcing.h"}
    assert all(p.parent == build.CSRC for p in texts)
    py = [p for p in SRC.rglob("*.py") if "fc.harm_w" in p.read_text()]
    assert [p.name for p in py] == ["forcing.py"]


@pytest.mark.parametrize("method", ["NT", "NP"])
def test_orbit_rhs_equals_simulation_rhs_at_held_wheel_rate(method):
    """HR at 5 m/s: at random off-equilibrium states and times, the orbit's right-hand side
    (po_rhs, rear-wheel rate held by the hub torque tau) equals the simulation library's
    forced right-hand side with that hub torque (forced_rhs_hub): the same roll, pitch, steer
    rates and roll/steer accelerations to 1e-12, and a rear-wheel acceleration of zero. With
    tau = 0, forced_rhs_hub is forced_rhs itself (bit for bit)."""
    from pedalrepro.nonlinear.forcing import ForcingStruct, fill_forcing
    from pedalrepro.nonlinear.simulate import ForcedModel

    omega = 2 * np.pi
    s = periodic.OrbitSolver("HR", method, omega)
    speed = 5.0
    s.set_speed(speed)
    nl = s.nl
    lib = nl.lib
    fc = ForcingStruct()
    keep = fill_forcing(fc, nl, s.harmonics if method == "NT" else None, omega)
    forced = ForcedModel(nl, s.harmonics if method == "NT" else None, omega).compiled()
    rng = np.random.default_rng(1)
    worst, checked = 0.0, 0
    for t in rng.uniform(0.0, s.period_s, 6):
        z = rng.normal(scale=[0.05, 0.05, 0.3, 0.3])
        y, _ = s.state(z)
        dy, tau = s.rhs(t, y)
        x = np.array([y[0], y[1], y[2], y[3], -speed / s.r_rear_m, y[4]])
        dx = np.empty(6)
        assert lib.forced_rhs_hub(ctypes.byref(fc), float(t), x.ctypes.data, float(tau),
                                  dx.ctypes.data) == 0
        scale = max(1.0, float(np.max(np.abs(dx))))
        worst = max(worst, float(np.max(np.abs(dx[[0, 1, 2, 3, 5]] - dy))) / scale,
                    abs(float(dx[4])) / scale)
        dx0 = np.empty(6)
        assert lib.forced_rhs_hub(ctypes.byref(fc), float(t), x.ctypes.data, 0.0,
                                  dx0.ctypes.data) == 0
        np.testing.assert_array_equal(dx0, forced.evaluate(t, x))
        assert abs(tau) > 1e-3  # the hold is doing work: the test compares a loaded case
        checked += 1
    del keep
    assert checked == 6
    assert worst <= 1e-12, worst


#: Fused multiply-add instructions: x86-64 (FMA3/AVX-512: vfmadd231sd, vfmsubadd132pd, ...) and
#: AArch64 (fmadd, fnmsub, fmla, ...).
_FUSED = re.compile(r"\b(v?fn?m(add|sub)(sub|add)?\d{3}[sp][sd]|fn?m(add|sub)|fml[as])\b")


@pytest.mark.parametrize("variant", ["plain", "legs_arms"])
def test_compiled_libraries_round_every_operation_separately(variant):
    """Every multiplication and addition of the simulation and periodic-orbit libraries is
    rounded on its own (``-ffp-contract=off``): no fused multiply-add instruction in the machine
    code. GCC 12's straight-line vectoriser made one (``vfmsubadd``) out of the generated model
    code despite that flag, so that a change of the hand-written solve moved results by an ulp
    (and 13 chaotic NT runs); ``-fno-tree-slp-vectorize`` in ``build.CFLAGS`` prevents it."""
    if shutil.which("objdump") is None:
        skip_unless_required(CC, "binutils' objdump (installed with the C compiler) not found")
    from pedalrepro.nonlinear import codegen, library, symbolic
    from pedalrepro.periodic import solver

    options = symbolic.ModelOptions(legs="legs" in variant, arms="arms" in variant)
    model_c = codegen.generated_c(options)
    libs = [library.compiled_library(options),
            build.build(solver.PERIODIC_LIBRARY_C, codegen.cache_dir(), "periodic",
                        model_c=model_c)]
    for so in libs:
        code = subprocess.run(["objdump", "-d", "--no-show-raw-insn", str(so)],
                              capture_output=True, text=True, check=True).stdout
        fused = sorted(set(_FUSED.findall(code)))
        assert code.count("\n") > 1000  # the disassembly is there
        assert not _FUSED.search(code), (so, fused)
