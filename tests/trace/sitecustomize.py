"""Record what a process really reads (for tests/workflow/test_change_tracking.py; off unless
asked).

Loaded by the tests, never by the package: the session fixture ``quick_workflow``
(tests/conftest.py) puts this folder first on ``PYTHONPATH`` and sets ``PEDALREPRO_TRACE=<folder>``
for its Snakemake run, so every Python process of the run (Snakemake, each rule script, the
book's notebook kernels) imports this ``sitecustomize`` at start-up. It installs an audit hook
(:func:`sys.addaudithook`) noting every file opened under ``data/`` and every non-Python file of
the package, and at exit writes ``<folder>/<pid>.json``: the program (``sys.argv[0]``; a rule
script runs as ``.snakemake/scripts/tmpXXXX.<script>.py``), those files and the pedalrepro
modules loaded. The test checks both against :func:`pedalrepro.dependencies.code_inputs` of the
rule's script, so a module reading a file its rule does not declare fails CI.
"""

from __future__ import annotations

import atexit
import importlib.util
import json
import os
import sys
from pathlib import Path


def install(folder: str | os.PathLike) -> None:
    """Start recording (once per process)."""
    if getattr(install, "done", False):
        return
    install.done = True
    spec = importlib.util.find_spec("pedalrepro")  # finds the package without importing it
    if spec is None or spec.origin is None:
        return
    package = Path(spec.origin).resolve().parent
    root = package.parents[1]
    watched = (str(root / "data") + os.sep, str(package) + os.sep)
    opened: set[str] = set()

    def hook(event: str, args: tuple) -> None:
        if event != "open" or not args or isinstance(args[0], int):
            return
        try:
            path = os.path.abspath(os.fsdecode(args[0]))
        except (TypeError, ValueError):
            return
        if path.startswith(watched) and not path.endswith((".py", ".pyc")):
            opened.add(os.path.relpath(path, root))

    def dump() -> None:
        modules = sorted(
            os.path.relpath(os.path.abspath(m.__file__), root)
            for name, m in list(sys.modules.items())
            if (name == "pedalrepro" or name.startswith("pedalrepro."))
            and getattr(m, "__file__", None))
        out = Path(folder)
        out.mkdir(parents=True, exist_ok=True)
        (out / f"{os.getpid()}.json").write_text(json.dumps(
            {"argv0": sys.argv[0] if sys.argv else "", "cwd": os.getcwd(),
             "files": sorted(opened), "modules": modules}))

    sys.addaudithook(hook)
    atexit.register(dump)


if os.environ.get("PEDALREPRO_TRACE"):
    install(os.environ["PEDALREPRO_TRACE"])
