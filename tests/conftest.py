"""Shared pytest fixtures."""

from __future__ import annotations

import pytest

from pedalrepro import params


@pytest.fixture(scope="session")
def published() -> dict:
    """The thesis's published numbers (expected values only)."""
    return params.published()


# --- The end-to-end quick-profile run (book part), shared by the tests of tests/workflow/
# --- (test_workflow.py, test_book_browser.py, test_section2_workflow.py, ...) and the built-book
# --- tests, so the browser test checks the very book the workflow built.
@pytest.fixture(scope="session")
def quick_workflow():
    """Run ``snakemake -j2 --configfile config/quick.yaml`` once per session into a fresh results
    folder (``results/pytest_quick``, or ``$PEDALREPRO_TEST_RESULTS``; kept, not wiped, when
    ``PEDALREPRO_TEST_KEEP_RESULTS=1``).

    Every pedalrepro process of the run records the files and modules it reads into
    ``<results>.trace/`` (``PEDALREPRO_TRACE``, tests/trace/sitecustomize.py; checked by
    tests/workflow/test_change_tracking.py).

    Returns a namespace: results, returncode, log, elapsed_s, trace, and snakemake_log: the
    run's own log in ``.snakemake/log`` (None if Snakemake named none), which a later Snakemake
    run of the session does not replace (tests/workflow/test_bench_pipeline.py reads it)."""
    import os
    import shutil
    import subprocess
    import sys
    import time
    from pathlib import Path
    from types import SimpleNamespace

    from pedalrepro import paths

    default = paths.ROOT / "results" / "pytest_quick"
    results = Path(os.environ.get("PEDALREPRO_TEST_RESULTS", default)).resolve()
    results.parent.mkdir(parents=True, exist_ok=True)
    # Another pytest session using the same folder (several people in one checkout)? Then use a
    # folder of our own instead of wiping theirs.
    lock = results.parent / f"{results.name}.pid"
    try:
        other = int(lock.read_text())
        os.kill(other, 0)
        in_use = other != os.getpid()
    except (OSError, ValueError):
        in_use = False
    if in_use:
        results = results.parent / f"{results.name}_{os.getpid()}"
        lock = results.parent / f"{results.name}.pid"
    lock.write_text(str(os.getpid()))
    trace = results.parent / f"{results.name}.trace"
    if os.environ.get("PEDALREPRO_TEST_KEEP_RESULTS") != "1":
        for folder in (results, trace):
            if folder.exists():
                shutil.rmtree(folder)
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    env["PEDALREPRO_TRACE"] = str(trace)
    # tests/trace/sitecustomize.py records what each process of the run reads (the package
    # itself never loads it)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(Path(__file__).resolve().parent / "trace")]
        + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    cmd = [sys.executable, "-m", "snakemake", "-j2", "--configfile", "config/quick.yaml",
           "--config", f"results_dir={results}"]
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=paths.ROOT, env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    log = proc.stdout + proc.stderr
    (results.parent / f"{results.name}.snakemake.log").write_text(
        f"$ {' '.join(cmd)}\n# {elapsed:.1f} s, exit {proc.returncode}\n{log}")
    import re

    named = re.findall(r"^Complete log\(s\): (\S+)$", log, re.M)
    return SimpleNamespace(results=results, returncode=proc.returncode, log=log, elapsed_s=elapsed,
                           trace=trace, snakemake_log=Path(named[-1]) if named else None)


# --- The symbolic non-linear models: derived once into ~/.cache/pedalrepro (2-4 min CPU on a
# --- cold cache). Tests whose module imports pedalrepro.nonlinear (directly or through the
# --- library; pedalrepro.dependencies) first warm the cache here, saying what they derive, so
# --- no "unit" test silently pays the derivation.
_WARMED: set[str] = set()


def _needs_nonlinear_models(test_file) -> bool:
    from pathlib import Path

    from pedalrepro import dependencies

    codegen = dependencies.PACKAGE_DIR / "nonlinear" / "codegen.py"
    return codegen in dependencies.import_closure([Path(str(test_file))])


@pytest.fixture(scope="session")
def nonlinear_cache(request):
    """Derive and compile every missing symbolic model variant (plain, legs, arms, legs + arms),
    printing each one; returns the cache folder. A warm cache costs file look-ups only."""
    import time

    from pedalrepro.nonlinear import codegen, library, symbolic

    capture = request.config.pluginmanager.getplugin("capturemanager")
    for legs in (False, True):
        for arms in (False, True):
            options = symbolic.ModelOptions(legs=legs, arms=arms)
            key = codegen.cache_key(options)
            folder = codegen.cache_dir()
            if (folder / f"{key}.py").exists() and any(folder.glob(f"{key}.*.so")):
                continue
            with capture.global_and_fixture_disabled():
                print(f"\n[nonlinear_cache] deriving {options.key()} into {codegen.cache_dir()} "
                      "(once; about 10-120 s)...", flush=True)
            start = time.perf_counter()
            codegen.generated_source(options)
            library.compiled_library(options)
            with capture.global_and_fixture_disabled():
                print(f"[nonlinear_cache] {options.key()} done in "
                      f"{time.perf_counter() - start:.0f} s", flush=True)
    return codegen.cache_dir()


@pytest.fixture(autouse=True)
def _warm_nonlinear_models(request):
    """Request :func:`nonlinear_cache` for tests in modules reaching pedalrepro.nonlinear."""
    path = str(request.node.fspath)
    if path not in _WARMED:
        _WARMED.add(path)
        if _needs_nonlinear_models(path):
            request.getfixturevalue("nonlinear_cache")
