"""Build the compiled code (``pedalrepro/csrc``) into cached shared libraries.

The hand-written C lives in one folder, :data:`CSRC`: shared headers (``lu.h``, ``dopri.h`` with
the Dormand-Prince tableau and step, the sampled loop ``dopri_sampled.h``, the flow loop
``dopri_flow.h``, ``forcing.h``, the model's null-space right-hand side ``model_rhs.h``,
``linear_rhs.h``) and three entry files composed from them with ``#include``:
``linear_library.c``, ``model_library.c`` (simulation) and ``periodic_library.c`` (orbits). The
last two include a model's generated code by name (``-DMODEL_C`` and ``-I`` its folder).

Libraries live in ``$PEDALREPRO_CACHE`` (default ``~/.cache/pedalrepro``), named after a hash
of every source they include (the entry file, its headers and the generated model code), the
compiler flags and the machine (:func:`machine_tag`): a changed source builds a new library, an
unchanged one is reused. Written atomically (parallel jobs never load a half-written file).
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import platform
import re
import shutil
import subprocess
from functools import cache
from pathlib import Path

__all__ = [
    "CSRC", "DATA_FILES", "cache_root", "compiler", "CFLAGS", "FALLBACK_CFLAGS", "machine_tag",
    "source_hash", "sources", "build", "declare", "linear_library",
]

#: The hand-written C: shared headers and the entry file of each library.
CSRC = Path(__file__).resolve().parents[1] / "csrc"
#: The files of the linear library (change tracking, :mod:`pedalrepro.dependencies`); the
#: model and periodic libraries declare theirs in :mod:`pedalrepro.nonlinear.library` and
#: :mod:`pedalrepro.periodic.solver`.
DATA_FILES: tuple[str, ...] = ("src/pedalrepro/csrc/linear_library.c",
                               "src/pedalrepro/csrc/linear_rhs.h",
                               "src/pedalrepro/csrc/dopri_sampled.h",
                               "src/pedalrepro/csrc/dopri.h")
_INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def cache_root() -> Path:
    """``$PEDALREPRO_CACHE`` or ``~/.cache/pedalrepro``."""
    env = os.environ.get("PEDALREPRO_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "pedalrepro"


def compiler() -> str | None:
    """The C compiler (``$CC``, gcc or cc), or None."""
    return shutil.which(os.environ.get("CC", "gcc")) or shutil.which("cc")


#: Compiler flags. ``-O3 -march=native`` runs the thesis-grid NT/NP sweeps about 20 % faster than
#: ``-O2`` (measured, scripts/bench_nonlinear.py); ``-ffp-contract=off`` keeps every
#: multiplication and addition separately rounded, so the results equal ``-O2``'s to the bit.
#: ``-fno-tree-slp-vectorize``: GCC 12's straight-line vectoriser fuses an alternating
#: add/subtract pair of the generated model code into ``vfmsubadd`` (a fused multiply-add, one
#: rounding) despite ``-ffp-contract=off``; it did so in model_rhs once the dependent speeds'
#: solve changed (lu_solve_columns), moving a dependent speed by 2e-5 relative of its 4e-19 and
#: changing 13 chaotic (falling) NT runs of CR. Without it the build has no fused operation and
#: equals the earlier builds to the bit, at about 5 % of the right-hand side's time
#: (0.84 -> 0.90 us per model_held_rhs call, measured on this machine).
CFLAGS: tuple[str, ...] = ("-O3", "-march=native", "-ffp-contract=off",
                           "-fno-tree-slp-vectorize")
#: Flags of a second attempt when the compiler rejects :data:`CFLAGS` (``-march=native`` is not
#: supported everywhere).
FALLBACK_CFLAGS: tuple[str, ...] = ("-O2",)


@cache
def machine_tag() -> str:
    """What a ``-march=native`` library depends on besides its source: the compiler and the CPU
    (model and feature flags from ``/proc/cpuinfo`` where it exists). A cache folder shared by
    different machines (a cluster's home directory) so holds one library per CPU type."""
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
        cpu = "\n".join(next((ln for ln in lines if ln.startswith(k)), "")
                        for k in ("model name", "flags", "Features", "CPU part"))
    except OSError:
        cpu = ""
    return "\n".join([compiler() or "", platform.machine(), platform.processor(), cpu])


def source_hash(text: str) -> str:
    """First 16 hex digits of the SHA-256 of ``text``."""
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def sources(entry: str, csrc: Path = CSRC) -> list[Path]:
    """``csrc/<entry>`` and every file of ``csrc`` it includes with ``#include "..."``
    (recursively), sorted by name: the hand-written sources of one library."""
    found: dict[str, Path] = {}
    todo = [entry]
    while todo:
        name = todo.pop()
        if name in found:
            continue
        path = csrc / name
        found[name] = path
        todo.extend(n for n in _INCLUDE.findall(path.read_text()) if (csrc / n).is_file())
    return [found[k] for k in sorted(found)]


def build(entry: str, folder: Path, stem: str, model_c: Path | None = None,
          csrc: Path = CSRC) -> Path | None:
    """``folder/<stem>.<hash>.so`` compiled from ``csrc/<entry>`` (once), or None without a C
    compiler. ``model_c``: the generated model code the entry includes as ``MODEL_C``. The hash
    covers the entry and what it includes (:func:`sources`), the model code, :data:`CFLAGS` and
    :func:`machine_tag`."""
    text = "\n".join(f"/* {p.name} */\n{p.read_text()}" for p in sources(entry, csrc))
    text += model_c.read_text() if model_c is not None else ""
    so = folder / f"{stem}.{source_hash(text + chr(10).join(CFLAGS) + machine_tag())}.so"
    if so.exists():
        return so
    cc = compiler()
    if cc is None:
        return None
    folder.mkdir(parents=True, exist_ok=True)
    extra = ["-I", str(csrc)]
    if model_c is not None:
        extra += ["-I", str(model_c.parent), f'-DMODEL_C="{model_c.name}"']
    tmp = so.with_suffix(f".tmp{os.getpid()}.so")  # per process: no torn reads
    for flags in (CFLAGS, FALLBACK_CFLAGS):
        done = subprocess.run([cc, *flags, *extra, "-shared", "-fPIC", "-o", str(tmp),
                               str(csrc / entry), "-lm"], capture_output=True, text=True)
        if done.returncode == 0:
            break
    else:
        raise RuntimeError(f"C compiler {cc} failed on {csrc / entry}:\n{done.stderr[-2000:]}")
    tmp.replace(so)
    return so


def declare(lib: ctypes.CDLL) -> ctypes.CDLL:
    """Argument types of the integrator's entry points (``dopri_integrate``, ``dopri_eval``)."""
    dp, ci = ctypes.c_void_p, ctypes.c_int
    lib.dopri_integrate.argtypes = [dp, dp, ci, dp, dp, ci, dp, dp, ctypes.POINTER(ctypes.c_double),
                                    ctypes.POINTER(ctypes.c_long)]
    lib.dopri_integrate.restype = ci
    lib.dopri_eval.argtypes = [dp, dp, ctypes.c_double, dp, dp]
    lib.dopri_eval.restype = ci
    return lib


@cache
def linear_library() -> ctypes.CDLL | None:
    """The integrator with the linear right-hand side (:mod:`pedalrepro.integrator.linear`), or
    None (no compiler)."""
    path = build("linear_library.c", cache_root() / "integrator", "linear")
    return None if path is None else declare(ctypes.CDLL(str(path)))
