"""CONTRIBUTING's checkable rules: ``ruff check .`` is clean, notebooks included.

(``snakemake --lint`` is checked in tests/workflow/test_workflow.py.)
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


#: Rules that share a script, and why: the two linear time-solution methods run one script
#: (the method is a parameter), and every figure group runs the registry's one drawing script.
SHARED_SCRIPTS = {"linear_time_la": "linear_time", "linear_time_ln": "linear_time"}


def _rules() -> dict[str, dict[str, str]]:
    """Rule name -> {"script", "log", "benchmark"} from ``rules/*.smk`` (named rules; the figure
    groups' rules, made in a loop, are checked separately)."""
    import re

    out = {}
    for smk in sorted((paths.ROOT / "rules").glob("*.smk")):
        text = smk.read_text()
        starts = [m for m in re.finditer(r"^rule (\w+):", text, re.M)]
        for k, m in enumerate(starts):
            end = starts[k + 1].start() if k + 1 < len(starts) else len(text)
            body = text[m.end():end]
            found = {}
            for key, pattern in (("script", r'script:\s*"scripts/(\w+)\.py"'),
                                 ("log", r'logfile\(f?"([^"]+)"\)'),
                                 ("benchmark", r'bench\(f?"([^"]+)"\)')):
                hit = re.search(pattern, body)
                if hit:
                    found[key] = hit.group(1)
            out[m.group(1)] = found
    return out


def test_rule_script_log_and_benchmark_share_the_rule_name():
    """CONTRIBUTING: a rule's script is ``rules/scripts/<rule>.py`` (except the rules of
    :data:`SHARED_SCRIPTS`), and its log and benchmark files are ``<rule>`` or
    ``<rule>_<wildcards>``, so a rule, its script and its log are found by one name. The figure
    groups' rules are ``figures_<group>``, logging as such and running ``scripts/figures.py``."""
    rules = _rules()
    assert len(rules) >= 40, sorted(rules)  # every named rule was parsed
    bad = []
    for name, found in rules.items():
        script = found.get("script")
        if script is not None and script != SHARED_SCRIPTS.get(name, name):
            bad.append(f"rule {name} runs scripts/{script}.py")
        for key in ("log", "benchmark"):
            stem = found.get(key)
            if stem is None:
                bad.append(f"rule {name} has no {key}")
            elif stem != name and not stem.startswith(f"{name}_{{"):
                bad.append(f"rule {name} writes its {key} as {stem}")
    assert not bad, bad
    scripts = {p.stem for p in (paths.ROOT / "rules" / "scripts").glob("*.py")}
    run = {f.get("script") for f in rules.values()} | {"figures"}
    assert scripts == run - {None}, ("scripts no rule runs", scripts - run)
    figures_smk = (paths.ROOT / "rules" / "figures.smk").read_text()
    assert 'f"figures_{_group}"' in figures_smk and 'logfile(f"figures_{_group}")' in figures_smk
    assert 'bench(f"figures_{_group}")' in figures_smk and '"scripts/figures.py"' in figures_smk
