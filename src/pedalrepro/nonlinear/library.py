"""The compiled right-hand side of a non-linear model, with the integrator compiled in.

One shared library per model variant: the generated C of :func:`.codegen.generated_c`, the
hand-written driver ``rhs_driver.c`` (dependent speeds from ``A u = 0``, Kane's equations
reduced to the independent accelerations, the forcing) and the integrator
``pedalrepro/integrator/dopri.c``. Its name hashes that whole source
(:func:`pedalrepro.integrator.build.build`), so editing the hand-written C only recompiles
(seconds) and never re-derives. Called through ctypes.
"""

from __future__ import annotations

import ctypes
from functools import cache
from pathlib import Path

from ..integrator import build
from . import codegen
from . import model as symbolic

#: The hand-written part of the model's C code.
RHS_DRIVER_C = Path(__file__).with_name("rhs_driver.c")
#: The pedalling forcing (torques and prescribed legs), shared with the periodic-orbit driver.
FORCING_C = Path(__file__).with_name("forcing.c")


def library_source(options: symbolic.ModelOptions) -> str:
    """Full C source of the model's library (generated + forcing + driver + integrator)."""
    return "\n".join([codegen.generated_c(options).read_text(), FORCING_C.read_text(),
                      RHS_DRIVER_C.read_text(), build.DOPRI_C.read_text()])


def compiled_library(options: symbolic.ModelOptions) -> Path | None:
    """Path of the compiled library (built once, cached), or None without a C compiler.

    The full source is kept beside it (same name, ``.c``)."""
    if build.compiler() is None:
        return None
    return build.build(library_source(options), codegen.cache_dir(),
                       codegen.cache_key(options))


@cache
def load_library(options: symbolic.ModelOptions) -> ctypes.CDLL | None:
    """ctypes handle of the compiled library (``full_rhs``, ``forced_rhs``, ``dopri_*``), or
    None (no C compiler)."""
    path = compiled_library(options)
    if path is None:
        return None
    lib = build.declare(ctypes.CDLL(str(path)))
    dp = ctypes.c_void_p
    lib.full_rhs.argtypes = [dp, dp, dp, ctypes.c_double, ctypes.c_double, dp, dp]
    lib.full_rhs.restype = ctypes.c_int
    return lib
