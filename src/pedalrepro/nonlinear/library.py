"""The compiled right-hand side of a non-linear model, with the integrator compiled in.

One shared library per model variant, built from ``pedalrepro/csrc/model_library.c``: the
generated C of :func:`.codegen.generated_c` (included by name), the forcing (``forcing.h``), the
null-space right-hand side (``model_rhs.h``: dependent speeds from ``A u = 0``, Kane's equations
reduced to the independent accelerations) and the sampled Dormand-Prince loop with fall events
(``dopri_sampled.h``). Its name hashes every hand-written C file and the generated code
(:func:`pedalrepro.integrator.build.build`), so editing the hand-written C only recompiles
(seconds) and never re-derives. Called through ctypes.
"""

from __future__ import annotations

import ctypes
from functools import cache
from pathlib import Path

from ..integrator import build
from . import codegen, symbolic

__all__ = ["MODEL_LIBRARY_C", "DATA_FILES", "compiled_library", "load_library"]

#: Entry file of the simulation library (in :data:`pedalrepro.integrator.build.CSRC`).
MODEL_LIBRARY_C = "model_library.c"
#: Its hand-written sources besides the integrator's (change tracking).
DATA_FILES: tuple[str, ...] = ("src/pedalrepro/csrc/model_library.c",
                               "src/pedalrepro/csrc/model_rhs.h", "src/pedalrepro/csrc/lu.h",
                               "src/pedalrepro/csrc/forcing.h")


def compiled_library(options: symbolic.ModelOptions, csrc: Path = build.CSRC) -> Path | None:
    """Path of the compiled library (built once, cached), or None without a C compiler.
    ``csrc``: the folder of the hand-written C (tests pass an edited copy)."""
    if build.compiler() is None:
        return None
    return build.build(MODEL_LIBRARY_C, codegen.cache_dir(), codegen.cache_key(options),
                       model_c=codegen.generated_c(options), csrc=csrc)


@cache
def load_library(options: symbolic.ModelOptions) -> ctypes.CDLL | None:
    """ctypes handle of the compiled library (``full_rhs``, ``forced_rhs``,
    ``forced_rhs_hub``, ``dopri_*``), or None (no C compiler)."""
    path = compiled_library(options)
    if path is None:
        return None
    lib = build.declare(ctypes.CDLL(str(path)))
    dp, cd = ctypes.c_void_p, ctypes.c_double
    lib.full_rhs.argtypes = [dp, dp, dp, cd, cd, dp, dp]
    lib.full_rhs.restype = ctypes.c_int
    lib.forced_rhs_hub.argtypes = [dp, cd, dp, cd, dp]
    lib.forced_rhs_hub.restype = ctypes.c_int
    return lib
