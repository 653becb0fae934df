"""CONTRIBUTING's checkable rules: ``ruff check .`` is clean, notebooks included.

(``snakemake --lint`` is checked in tests/test_workflow.py.)
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from pedalrepro import paths


def ruff(*args: str) -> subprocess.CompletedProcess:
    exe = shutil.which("ruff", path=str(Path(sys.executable).parent)) or shutil.which("ruff")
    assert exe, "ruff is not installed (pip install -e '.[test]')"
    return subprocess.run([exe, *args], cwd=paths.ROOT, capture_output=True, text=True)


def test_ruff_checks_every_notebook_and_rule_script():
    shown = {Path(line.strip()).resolve() for line in ruff("check", "--show-files", ".")
             .stdout.splitlines() if line.strip()}
    wanted = set((paths.ROOT / "notebooks").glob("*.ipynb")) | set(
        (paths.ROOT / "rules" / "scripts").glob("*.py"))
    missing = sorted(str(p.relative_to(paths.ROOT)) for p in wanted if p.resolve() not in shown)
    assert not missing, f"ruff does not check: {missing}"


def test_ruff_clean():
    proc = ruff("check", ".")
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
