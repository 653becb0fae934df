"""Build C sources into a cached shared library (the compiled integrator and right-hand sides).

Libraries live in ``$PEDALREPRO_CACHE`` (default ``~/.cache/pedalrepro``), named after a hash
of their full source text, the compiler flags and the machine (:func:`machine_tag`): a changed
source builds a new library, an unchanged one is reused. Written atomically (parallel jobs never
load a half-written file).
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import platform
import shutil
import subprocess
from functools import cache
from pathlib import Path

#: The generic integrator (Dormand-Prince 5(4) with fall events), compiled into every library.
DOPRI_C = Path(__file__).with_name("dopri.c")
#: Right-hand side of a linear system with harmonic forcing.
LINEAR_RHS_C = Path(__file__).with_name("linear_rhs.c")


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
CFLAGS: tuple[str, ...] = ("-O3", "-march=native", "-ffp-contract=off")
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


def build(source: str, folder: Path, stem: str) -> Path | None:
    """``folder/<stem>.<hash of source>.so`` compiled from ``source`` (once), or None without a
    C compiler. The source is kept beside it as ``.c`` for reading."""
    so = folder / f"{stem}.{source_hash(source + chr(10).join(CFLAGS) + machine_tag())}.so"
    if so.exists():
        return so
    cc = compiler()
    if cc is None:
        return None
    folder.mkdir(parents=True, exist_ok=True)
    c_tmp = folder / f"{so.stem}.{os.getpid()}.c"  # per process: no torn reads
    c_tmp.write_text(source)
    tmp = so.with_suffix(f".tmp{os.getpid()}.so")
    for flags in (CFLAGS, FALLBACK_CFLAGS):
        done = subprocess.run([cc, *flags, "-shared", "-fPIC", "-o", str(tmp), str(c_tmp),
                               "-lm"], capture_output=True, text=True)
        if done.returncode == 0:
            break
    else:
        raise RuntimeError(f"C compiler {cc} failed on {c_tmp}:\n{done.stderr[-2000:]}")
    tmp.replace(so)
    c_tmp.replace(so.with_suffix(".c"))
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
    source = (DOPRI_C.read_text() + "\n" + LINEAR_RHS_C.read_text())
    path = build(source, cache_root() / "integrator", "linear")
    return None if path is None else declare(ctypes.CDLL(str(path)))
