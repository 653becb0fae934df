"""Shared pytest fixtures."""

from __future__ import annotations

import pytest

from pedalrepro import params


@pytest.fixture(scope="session")
def published() -> dict:
    """The thesis's published numbers (expected values only)."""
    return params.published()


# --- The end-to-end quick-profile run (book part), shared by tests/test_workflow.py and
# --- tests/test_book_browser.py so the browser test checks the very book the workflow built.
@pytest.fixture(scope="session")
def quick_workflow():
    """Run ``snakemake -j2 --configfile config/quick.yaml`` once per session into a fresh results
    folder (``results/pytest_quick``, or ``$PEDALREPRO_TEST_RESULTS``; kept, not wiped, when
    ``PEDALREPRO_TEST_KEEP_RESULTS=1``).

    Returns a namespace: results, returncode, log, elapsed_s."""
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
    if results.exists() and os.environ.get("PEDALREPRO_TEST_KEEP_RESULTS") != "1":
        shutil.rmtree(results)
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    cmd = [sys.executable, "-m", "snakemake", "-j2", "--configfile", "config/quick.yaml",
           "--config", f"results_dir={results}"]
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=paths.ROOT, env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    log = proc.stdout + proc.stderr
    (results.parent / f"{results.name}.snakemake.log").write_text(
        f"$ {' '.join(cmd)}\n# {elapsed:.1f} s, exit {proc.returncode}\n{log}")
    return SimpleNamespace(results=results, returncode=proc.returncode, log=log, elapsed_s=elapsed)
