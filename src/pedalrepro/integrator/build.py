"""Build C sources into a cached shared library (the compiled integrator and right-hand sides).

Libraries live in ``$PEDALREPRO_CACHE`` (default ``~/.cache/pedalrepro``), named after a hash
of their full source text: a changed source builds a new library, an unchanged one is reused.
Written atomically (parallel jobs never load a half-written file).
"""

from __future__ import annotations

import ctypes
import hashlib
import os
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


def source_hash(text: str) -> str:
    """First 16 hex digits of the SHA-256 of ``text``."""
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def build(source: str, folder: Path, stem: str) -> Path | None:
    """``folder/<stem>.<hash of source>.so`` compiled from ``source`` (once), or None without a
    C compiler. The source is kept beside it as ``.c`` for reading."""
    so = folder / f"{stem}.{source_hash(source)}.so"
    if so.exists():
        return so
    cc = compiler()
    if cc is None:
        return None
    folder.mkdir(parents=True, exist_ok=True)
    c_tmp = folder / f"{so.stem}.{os.getpid()}.c"  # per process: no torn reads
    c_tmp.write_text(source)
    tmp = so.with_suffix(f".tmp{os.getpid()}.so")
    subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", str(tmp), str(c_tmp), "-lm"],
                   check=True, capture_output=True)
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
