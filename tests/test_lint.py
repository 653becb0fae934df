"""CONTRIBUTING's checkable rules, as static checks of the sources: ``ruff check .`` is clean
(notebooks included), one name per rule, every rule's ``message:`` and named outputs, results
paths only through ``pedalrepro.paths``, no status typed in a script, no spelled-out model list,
notebooks reading the config copy and showing figures with a caption, the tests' layout and
skips, configuration loaded by the entry points only, comments citing repository files, README's
layout and the parameter files' sources.

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


# --------------------------------------------------------------------------------------------
# static checks of CONTRIBUTING's conventions
# --------------------------------------------------------------------------------------------

def _rule_bodies() -> dict[str, str]:
    """Rule name -> its text (up to the next top-level line) for every named rule of
    ``rules/*.smk`` and the Snakefile."""
    import re

    out = {}
    for smk in [*sorted((paths.ROOT / "rules").glob("*.smk")), paths.ROOT / "Snakefile"]:
        text = smk.read_text()
        for m in re.finditer(r"^rule (\w+):\n((?:[ \t]+.*\n|[ \t]*\n)*)", text, re.M):
            out[m.group(1)] = m.group(2)
    return out


def _directive_entries(body: str, directive: str) -> list[str]:
    """The comma-separated entries of a rule's directive (``output:``), brackets respected."""
    lines = body.splitlines()
    start = next((k for k, line in enumerate(lines) if line.strip() == f"{directive}:"), None)
    if start is None:
        return []
    indent = len(lines[start]) - len(lines[start].lstrip())
    block = []
    for line in lines[start + 1:]:
        if line.strip() and len(line) - len(line.lstrip()) <= indent:
            break
        block.append(line.split("#")[0] if not line.strip().startswith(("\"", "'")) else line)
    entries, depth, current = [], 0, ""
    for ch in "\n".join(block):
        depth += ch in "([{"
        depth -= ch in ")]}"
        if ch == "," and depth == 0:
            entries.append(current.strip())
            current = ""
        else:
            current += ch
    return [e for e in [*entries, current.strip()] if e]


def test_every_rule_has_a_message_and_names_its_outputs():
    """CONTRIBUTING: every rule has ``message:`` (beside ``log:`` and ``benchmark:``, checked
    above), and a rule with more than one output entry names each (``report=...``), so that its
    script reads ``snakemake.output.<name>``, not a position. ``rule all`` is the target list."""
    import re

    rules = _rule_bodies()
    assert len(rules) >= 40, sorted(rules)
    bad = []
    for name, body in rules.items():
        if name == "all":
            continue
        if not re.search(r"^\s+message:", body, re.M):
            bad.append(f"rule {name} has no message")
        outputs = _directive_entries(body, "output")
        if not outputs:
            bad.append(f"rule {name} has no output")
        elif len(outputs) > 1:
            bad += [f"rule {name}: unnamed output {e}" for e in outputs
                    if not re.match(r"\w+\s*=", e)]
    assert not bad, bad
    assert _directive_entries("    output:\n        a=f(x, y),\n        b=[1, 2],\n", "output") \
        == ["a=f(x, y)", "b=[1, 2]"]


def _python_sources(*folders: str) -> list[tuple[str, str]]:
    """(path relative to the repository, Python source) of the ``*.py`` files under ``folders``
    and of the notebooks' code cells (IPython magics blanked)."""
    import json

    out = []
    for folder in folders:
        for path in sorted((paths.ROOT / folder).rglob("*.py")):
            out.append((str(path.relative_to(paths.ROOT)), path.read_text()))
    if "notebooks" in folders:
        for path in sorted(paths.NOTEBOOKS.glob("*.ipynb")):
            cells = json.loads(path.read_text())["cells"]
            code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
            code = "\n".join("" if line.lstrip().startswith(("%", "!")) else line
                             for line in code.splitlines())
            out.append((str(path.relative_to(paths.ROOT)), code))
    return out


def hand_built_results_paths(source: str) -> list[str]:
    """Results paths a Python source builds without :mod:`pedalrepro.paths`: ``x / "tables"``
    (any folder of ``paths.LAYOUT``), ``f"{root}/figures/..."`` and ``"results/..."`` literals
    (help texts of command-line options excepted)."""
    import ast
    import re

    layout = "|".join(paths.LAYOUT.values())
    tree = ast.parse(source)
    helps = {id(k.value) for n in ast.walk(tree) if isinstance(n, ast.Call)
             for k in n.keywords if k.arg == "help"}
    bad = []
    for n in ast.walk(tree):
        if (isinstance(n, ast.BinOp) and isinstance(n.op, ast.Div)
                and isinstance(n.right, ast.Constant) and isinstance(n.right.value, str)
                and re.match(rf"({layout})(/|$)", n.right.value)):
            bad.append(f"line {n.lineno}: {ast.unparse(n)}")
        elif isinstance(n, ast.JoinedStr) and any(
                isinstance(a, ast.FormattedValue) and isinstance(b, ast.Constant)
                and re.match(rf"/({layout})/", str(b.value))
                for a, b in zip(n.values, n.values[1:], strict=False)):
            bad.append(f"line {n.lineno}: {ast.unparse(n)}")
        elif (isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in helps
              and re.match(r"(\./)?results/", n.value) and "\n" not in n.value):
            bad.append(f"line {n.lineno}: {n.value!r}")
    return bad


def test_results_paths_only_through_pedalrepro_paths():
    """CONTRIBUTING: paths under the results folder come from ``pedalrepro.paths`` (the library,
    rule scripts, scripts, notebooks) and from the helpers of ``rules/common.smk`` that call it
    (the rules files); only ``paths.py`` spells the layout."""
    import re

    bad = [f"{rel} {b}" for rel, src in _python_sources("src", "rules", "scripts", "notebooks")
           if rel != "src/pedalrepro/paths.py" for b in hand_built_results_paths(src)]
    layout = "|".join(paths.LAYOUT.values())
    for smk in [*sorted((paths.ROOT / "rules").glob("*.smk")), paths.ROOT / "Snakefile"]:
        for k, line in enumerate(smk.read_text().splitlines(), 1):
            if re.search(rf"\{{R\}}/({layout})/|/\s*[\"']({layout})[\"']", line.split("#")[0]):
                bad.append(f"{smk.relative_to(paths.ROOT)}:{k} {line.strip()}")
    assert not bad, bad
    assert len(hand_built_results_paths(
        'a = root / "tables"\nb = f"{R}/figures/x.png"\nc = "results/logs/x.log"\n'
        'ap.add_argument("--r", help="results/<...>")\nd = paths.table("x")\n')) == 3


def test_no_script_types_a_report_status():
    """CONTRIBUTING: a report row's status comes from ``pedalrepro.report.check`` only; no rule
    script or script spells a status (``"reproduced"``, ...) or imports the status constants."""
    import ast

    from pedalrepro.report import statuses

    constants = {n for n in dir(statuses) if n.isupper() and getattr(statuses, n) in
                 statuses.STATUSES}
    bad = []
    for rel, src in _python_sources("rules/scripts", "scripts"):
        for n in ast.walk(ast.parse(src)):
            if isinstance(n, ast.Constant) and n.value in statuses.STATUSES:
                bad.append(f"{rel}:{n.lineno} {n.value!r}")
            elif isinstance(n, ast.ImportFrom) and constants & {a.name for a in n.names}:
                bad.append(f"{rel}:{n.lineno} imports a status")
    assert constants and not bad, bad


def test_the_model_list_is_never_spelled_out():
    """CONTRIBUTING, "Interfaces": the thesis's models are ``pedalrepro.params.MODELS`` (or the
    list of the config key a rule uses); only ``params.py`` and the registry's ``MODELS4`` (kept
    free of the parameter files, pinned equal by tests/test_params.py) spell them."""
    import re

    names = r"[\"'](?:HS|CF|HR|CR|benchmark)[\"']"
    pattern = re.compile(rf"({names}\s*,\s*){{3,}}{names}")
    allowed = {"src/pedalrepro/params.py", "src/pedalrepro/figures/registry.py"}
    texts = [(rel, src) for rel, src in _python_sources("src", "rules", "scripts", "notebooks")
             if rel not in allowed]
    texts += [(str(p.relative_to(paths.ROOT)), p.read_text())
              for p in [*sorted((paths.ROOT / "rules").glob("*.smk")), paths.ROOT / "Snakefile"]]
    bad = [f"{rel}: {m.group(0)}" for rel, text in texts for m in pattern.finditer(text)]
    assert not bad, bad
    assert pattern.search('for m in ("HS", "CF", "HR", "CR")')


def test_notebooks_read_the_config_copy():
    """CONTRIBUTING: notebooks read the configuration a results folder was built with
    (``config.results_config()``), never ``config/config.yaml``."""
    bad = [rel for rel, src in _python_sources("notebooks") if rel.endswith(".ipynb")
           and any(s in src for s in ("config.yaml", "paths.CONFIG", "config.load("))]
    assert not bad, bad


def test_notebooks_show_figures_under_an_id_with_a_caption():
    """CONTRIBUTING, "Figures in the book": a notebook shows a figure through ``figures.show``
    (or ``book.show_file``), with a caption, never ``plt.show()``."""
    import ast

    bad = []
    for rel, src in _python_sources("notebooks"):
        if not rel.endswith(".ipynb"):
            continue
        for n in ast.walk(ast.parse(src)):
            if not (isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)):
                continue
            owner = ast.unparse(n.func.value)
            if n.func.attr == "show" and owner in ("plt", "fig"):
                bad.append(f"{rel}: {ast.unparse(n)}")
            elif (n.func.attr, owner) in {("show", "figures"), ("show", "book"),
                                          ("show_file", "book")}:
                need = 3 if n.func.attr == "show" else 2
                caption = next((k.value for k in n.keywords if k.arg == "caption"),
                               n.args[need - 1] if len(n.args) >= need else None)
                if caption is None or isinstance(caption, ast.Constant) and not caption.value:
                    bad.append(f"{rel}: no caption in {ast.unparse(n)[:80]}")
    assert not bad, bad


def test_tests_mirror_src_with_unique_names():
    """CONTRIBUTING: a test folder is a package of src/pedalrepro (``tests/figures/`` for
    ``pedalrepro.figures``) or ``tests/workflow/`` (the end-to-end checks); test files have
    unique names and there is no ``__init__.py`` (pytest imports them by basename)."""
    tests = paths.ROOT / "tests"
    files = sorted(tests.rglob("test_*.py"))
    assert not list(tests.rglob("__init__.py"))
    names = [p.name for p in files]
    assert len(names) == len(set(names)), sorted(n for n in names if names.count(n) > 1)
    packages = {p.parent.name for p in (paths.ROOT / "src" / "pedalrepro").glob("*/__init__.py")}
    folders = {p.parent.relative_to(tests).parts[0] for p in files if p.parent != tests}
    assert folders - packages == {"workflow"}, folders - packages


def test_only_required_py_skips():
    """CONTRIBUTING: a test whose input may be missing skips through tests/required.py, so
    that CI (its ``PEDALREPRO_REQUIRE_*`` flags) fails instead; the browser and cluster tests
    do the same with their own flags."""
    import re

    own_flag = {"tests/required.py", "tests/workflow/test_book_browser.py",
                "tests/workflow/test_cluster.py"}
    bad = []
    for rel, src in _python_sources("tests"):
        if rel in own_flag:
            continue
        for k, line in enumerate(src.splitlines(), 1):
            if re.search(r"pytest\.(skip\(|importorskip|mark\.skip)", line):
                bad.append(f"{rel}:{k} {line.strip()}")
    assert not bad, bad
    for rel in sorted(own_flag - {"tests/required.py"}):
        assert "PEDALREPRO_REQUIRE_" in (paths.ROOT / rel).read_text(), rel


def test_only_entry_points_load_a_configuration():
    """CONTRIBUTING: configuration reaches the library as explicit arguments; only
    ``pedalrepro.config`` and the command-line entry points that need one (``pedalrepro
    resonance``, ``pedalrepro report-status``) load a configuration file."""
    import re

    entry_points = {"src/pedalrepro/config.py", "src/pedalrepro/own_bicycle.py",
                    "src/pedalrepro/report/pinned.py"}
    loaders = re.compile(r"\b(config\.load|results_config)\(|CONFIG\s*/\s*[\"']config\.yaml")
    bad = [rel for rel, src in _python_sources("src") if rel not in entry_points
           and loaders.search("\n".join(line.split("#")[0] for line in src.splitlines()))]
    assert not bad, bad


def test_sources_cite_only_repository_files():
    """Comments and docstrings of the code, the rules and the configuration give the reason
    in words or name a file of the repository: no ``issue N`` (the tracker is not part of the
    repository) and no ``*.md`` file that does not exist here."""
    import re

    folders = ("src", "rules", "scripts", "profiles", "config", ".ci")
    files = [p for f in folders for p in sorted((paths.ROOT / f).rglob("*")) if p.is_file()
             and p.suffix in {"", ".py", ".smk", ".yaml", ".yml", ".sh", ".h", ".c", ".toml"}]
    files += [paths.ROOT / "Snakefile", paths.ROOT / "pyproject.toml"]
    bad = []
    for path in files:
        rel = path.relative_to(paths.ROOT)
        for k, line in enumerate(path.read_text().splitlines(), 1):
            if re.search(r"\bissues?\s+#?\d", line, re.I):
                bad.append(f"{rel}:{k} cites an issue")
            for md in re.findall(r"(?<![\w/.-])([\w./-]+\.md)\b", line):
                if not (paths.ROOT / md).is_file():
                    bad.append(f"{rel}:{k} cites {md}, not in the repository")
    assert not bad, bad


def test_readme_layout_lists_every_top_level_entry():
    """README's "Layout" names every folder (``scripts/``) and file the repository tracks at its
    top level (``.gitignore`` aside)."""
    import re

    tracked = subprocess.run(["git", "-C", str(paths.ROOT), "ls-files"], capture_output=True,
                             text=True, check=True).stdout.split()
    folders = {p.split("/")[0] for p in tracked if "/" in p}
    top_files = {p for p in tracked if "/" not in p} - {".gitignore"}
    readme = (paths.ROOT / "README.md").read_text()
    block = re.search(r"^## Layout\n+```\n(.*?)^```", readme, re.M | re.S).group(1)
    listed = {name.strip() for line in block.splitlines() if line and not line.startswith(" ")
              for name in re.split(r"\s{2,}", line, maxsplit=1)[0].split(",")}
    names = {n.split("/")[0] for n in listed}
    assert not (folders | top_files) - names, sorted((folders | top_files) - names)
    assert all(f"{d}/" in " ".join(listed) for d in folders), folders


def test_parameter_files_open_with_their_source():
    """CONTRIBUTING: parameters live in data/parameters/*.yaml with their source: each file
    opens with a comment saying where its numbers come from."""
    bad = [p.name for p in sorted(paths.PARAMETERS.glob("*.yaml"))
           if not p.read_text().startswith("# ")]
    assert not bad, bad
