"""Change tracking: every config value, module and data file reruns exactly the rules using it.

Three layers:

* ``pedalrepro.dependencies`` (the import closure behind ``code_inputs`` in rules/common.smk) on
  a small package written here, and on the project itself;
* the configuration checks (``config/schema.yaml`` + ``pedalrepro.config.check``), each failure
  naming its key, and one ``snakemake -n`` with a bad value;
* dry runs (``snakemake -n``) against the finished quick-profile run of the session fixture
  ``quick_workflow``: a changed config value, a touched module or a touched data file plans
  the rules using it (Snakemake's reason: params changed / updated input files), every other
  planned job only because an input is produced again (a dependent), and nothing else.
"""

from __future__ import annotations

import ast
import copy
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from pedalrepro import config, dependencies, paths
from pedalrepro.figures import registry as FIGURE_REGISTRY

RULE_SCRIPTS = sorted((paths.ROOT / "rules" / "scripts").glob("*.py"))
SMK_TEXT = "\n".join(p.read_text() for p in sorted((paths.ROOT / "rules").glob("*.smk")))
NOTEBOOKS = sorted(paths.NOTEBOOKS.glob("*.ipynb"))


# --------------------------------------------------------------------------------------------
# The import closure
# --------------------------------------------------------------------------------------------

def _write(root: Path, files: dict[str, str]) -> None:
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)


def test_closure_follows_every_import_form(tmp_path):
    """Relative (one and two dots), absolute dotted, imports inside functions, package
    __init__ files; unreached modules stay out, third-party imports are ignored."""
    pkg = tmp_path / "src" / "toy"
    _write(tmp_path, {
        "src/toy/__init__.py": "",
        "src/toy/a.py": "from . import b\n",
        "src/toy/b.py": "import numpy\n\ndef f():\n    from .sub import c\n    return c\n",
        "src/toy/sub/__init__.py": "",
        "src/toy/sub/c.py": "from .. import d\nfrom ..e import thing\n",
        "src/toy/d.py": "import toy.deep.leaf\n",
        "src/toy/e.py": "thing = 1\n",
        "src/toy/deep/__init__.py": "",
        "src/toy/deep/leaf.py": "",
        "src/toy/unused.py": "",
        "rules/scripts/job.py": "from toy import a\n",
    })
    got = dependencies.import_closure([tmp_path / "rules/scripts/job.py"], pkg)
    rel = sorted(str(p.relative_to(pkg)) for p in got)
    assert rel == ["__init__.py", "a.py", "b.py", "d.py", "deep/__init__.py", "deep/leaf.py",
                   "e.py", "sub/__init__.py", "sub/c.py"]


def test_code_inputs_include_declared_and_named_files(tmp_path):
    """DATA_FILES (a folder expands to its files) and a literal naming a data file or a package
    resource are inputs; paths.py only names locations and adds nothing."""
    _write(tmp_path, {
        "src/toy/__init__.py": "",
        "src/toy/paths.py": "STYLE = 'toy.mplstyle'\n",
        "src/toy/toy.mplstyle": "lines.linewidth: 1\n",
        "src/toy/driver.c": "int main(void) { return 0; }\n",
        "src/toy/load.py": ("from . import paths\nDATA_FILES = ('data/parameters/many',)\n"
                            "RUNS = 'runs.yaml'\nC = 'driver.c'\n"),
        "data/parameters/runs.yaml": "a: 1\n",
        "data/parameters/other.yaml": "a: 1\n",
        "data/parameters/many/x.txt": "1\n",
        "data/parameters/many/sub/y.txt": "2\n",
        "rules/scripts/job.py": "import toy.load\n",
    })
    got = dependencies.code_inputs("rules/scripts/job.py", root=tmp_path,
                                   package_dir=tmp_path / "src" / "toy")
    assert got == ["data/parameters/many/sub/y.txt", "data/parameters/many/x.txt",
                   "data/parameters/runs.yaml", "rules/scripts/job.py", "src/toy/__init__.py",
                   "src/toy/driver.c", "src/toy/load.py", "src/toy/paths.py"]


def test_declared_files_exist_and_are_literal():
    for module in sorted(dependencies.PACKAGE_DIR.rglob("*.py")):
        for rel in dependencies.declared_files(module):
            assert (paths.ROOT / rel).exists(), f"{module}: DATA_FILES names missing {rel}"


def _literal_parameter_files(path: Path) -> set[str]:
    """data/parameters/<name>.yaml of every literal argument of the computed-name loaders."""
    tree = ast.parse(dependencies.python_source(path))
    out = set()
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and node.args
                and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)
                and getattr(node.func, "attr", getattr(node.func, "id", None))
                in ("_parameter_file", "benchmark_parameters")):
            out.add(f"data/parameters/{node.args[0].value}.yaml")
    return out


#: The sources that read a parameter file by a computed name (a literal argument of
#: ``_parameter_file`` / ``benchmark_parameters``); the parametrised test below checks each one.
COMPUTED_NAME_READERS = [p for p in (*sorted(dependencies.PACKAGE_DIR.rglob("*.py")),
                                     *RULE_SCRIPTS, *NOTEBOOKS) if _literal_parameter_files(p)]


def test_computed_name_readers_are_found():
    """The scan finds the known readers (params.py loads stratos/browser by name), so the
    parametrised test below checks something."""
    names = {p.name for p in COMPUTED_NAME_READERS}
    assert "params.py" in names and len(names) >= 2, names


@pytest.mark.parametrize("source", COMPUTED_NAME_READERS, ids=lambda p: p.name)
def test_files_loaded_by_computed_name_are_inputs(source):
    """``params._parameter_file("stratos")`` or ``benchmark_parameters("browser")`` read a
    file whose name no literal spells: the closure of the caller must declare it."""
    needed = _literal_parameter_files(source)
    got = set(dependencies.code_inputs(source, root=paths.ROOT))
    assert needed <= got, f"{source.name} reads {sorted(needed - got)} undeclared"


def test_every_data_file_is_an_input_of_some_rule():
    """browser.yaml, stratos.yaml, bicycleparameters/ ... each reach at least one rule (the
    issue found three that reached none). rider_jason.yaml documents the rider; no code reads
    it (BicycleParameters reads the rider from bicycleparameters/riders/Jason)."""
    used = set(dependencies.code_inputs(*RULE_SCRIPTS, *NOTEBOOKS, root=paths.ROOT))
    unread = {"data/parameters/rider_jason.yaml"}
    for f in sorted((paths.DATA).rglob("*")):
        rel = str(f.relative_to(paths.ROOT))
        if f.is_file() and rel not in unread:
            assert rel in used, f"{rel} is no rule's input"


def test_rule_scripts_never_read_the_whole_config():
    for path in [*RULE_SCRIPTS, *sorted((paths.ROOT / "rules").glob("*.smk"))]:
        assert "snakemake.config" not in path.read_text(), path
    smk = "\n".join(p.read_text() for p in (paths.ROOT / "rules").glob("*.smk"))
    assert "pkg(" not in smk, "hand-listed modules: use code_inputs()"
    for script in RULE_SCRIPTS:
        assert f'code_inputs("scripts/{script.name}")' in smk, f"{script.name} has no code_inputs"


# --------------------------------------------------------------------------------------------
# Configuration checks
# --------------------------------------------------------------------------------------------

@pytest.fixture()
def quick_cfg():
    return config.merge(config.read_yaml(paths.CONFIG / "config.yaml"),
                        config.read_yaml(paths.CONFIG / "quick.yaml"))


def test_schema_describes_and_requires_every_key():
    schema = config.read_yaml(paths.CONFIG / "schema.yaml")
    cfg = config.read_yaml(paths.CONFIG / "config.yaml")

    def walk(node, value, key=""):
        props = node.get("properties", {})
        assert set(props) == set(node.get("required", [])), f"{key or '<top>'}: not all required"
        assert set(props) == set(value), f"{key or '<top>'}: schema and config.yaml differ"
        for k, sub in props.items():
            assert sub.get("description"), f"{key}{k} has no description"
            if isinstance(value[k], dict):
                walk(sub, value[k], f"{key}{k}.")

    walk(schema, cfg)


@pytest.mark.parametrize("key", [("linear", "harmonics"), ("linear", "tight_rtol"),
                                 ("mocap", "example_runs_per_system"), ("seed",)])
def test_missing_key_is_rejected_by_name(quick_cfg, key):
    target = quick_cfg
    for k in key[:-1]:
        target = target[k]
    del target[key[-1]]
    with pytest.raises(config.ConfigError, match=rf"'{key[-1]}' is a required property"):
        config.validate(quick_cfg)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_nan_and_inf_rejected_by_name(quick_cfg, value):
    """JSON schema lets .nan through (every comparison with NaN is false); check() does not."""
    quick_cfg["linear"]["rtol"] = value
    quick_cfg["linear"]["normal_cycling_speed_kmh"][1] = value
    if math.isnan(value):
        config.validate(quick_cfg)  # the schema alone lets NaN through
    with pytest.raises(config.ConfigError) as info:
        config.check(quick_cfg)
    assert "linear.rtol:" in str(info.value)
    assert "linear.normal_cycling_speed_kmh[1]:" in str(info.value)


def _check_fails(cfg, key, root=paths.ROOT):
    with pytest.raises(config.ConfigError) as info:
        config.check(cfg, root)
    assert re.search(rf"(^|\s){re.escape(key)}:", str(info.value)), str(info.value)
    return str(info.value)


def test_nyquist_of_the_time_grid(quick_cfg):
    """Highest harmonic: 5 x 4 pi rad/s = 10 Hz, so 20 Hz is the least sample rate (the issue's
    1.0 Hz aliased amplitudes to 0.788 rad instead of 0.0064); 20.5 Hz passes."""
    quick_cfg["linear"]["sample_rate_hz"] = 1.0
    msg = _check_fails(quick_cfg, "linear.sample_rate_hz")
    assert "10 Hz" in msg
    quick_cfg["linear"]["sample_rate_hz"] = 20.0
    _check_fails(quick_cfg, "linear.sample_rate_hz")
    quick_cfg["linear"]["sample_rate_hz"] = 20.5
    config.check(quick_cfg)
    quick_cfg["linear"]["harmonics"] = [1, 3, 5, 7]  # 14 Hz: 20.5 Hz aliases again
    _check_fails(quick_cfg, "linear.sample_rate_hz")


def test_lowpass_below_nyquist_of_the_mocap_rate(quick_cfg):
    quick_cfg["mocap"]["sample_rate_hz"] = 20.0
    quick_cfg["mocap"]["angle_lowpass_hz"] = 10.0
    _check_fails(quick_cfg, "mocap.angle_lowpass_hz")
    quick_cfg["mocap"]["angle_lowpass_hz"] = 0  # off: no constraint
    config.check(quick_cfg)


def test_section2_harmonics_below_nyquist(quick_cfg):
    quick_cfg["section2"]["samples_per_revolution"] = 64
    quick_cfg["section2"]["harmonics"] = 32
    _check_fails(quick_cfg, "section2.harmonics")


def test_duration_holds_one_period_of_the_slowest_cadence(quick_cfg):
    quick_cfg["linear"]["duration_s"] = 3.0  # quick: 2 rad/s step -> period pi s
    _check_fails(quick_cfg, "linear.duration_s")


@pytest.mark.parametrize("step, maximum", config.STEP_MAXIMA)
def test_each_step_below_its_maximum(quick_cfg, step, maximum):
    quick_cfg["linear"][step] = quick_cfg["linear"][maximum]
    _check_fails(quick_cfg, f"linear.{step}")


def test_normal_cycling_ranges_increase(quick_cfg):
    quick_cfg["linear"]["normal_cycling_cadence_rpm"] = [80.0, 50.0]
    _check_fails(quick_cfg, "linear.normal_cycling_cadence_rpm")


@pytest.mark.parametrize("folder", ["/", "/usr", "/etc", "/tmp", "~", ".", "/usr/../etc"])
def test_results_dir_not_a_system_folder(quick_cfg, folder):
    quick_cfg["results_dir"] = folder
    _check_fails(quick_cfg, "results_dir")


def test_results_dir_must_be_creatable(quick_cfg, tmp_path, monkeypatch):
    """The nearest existing parent must be writable (os.access faked: tests may run as root)."""
    locked = tmp_path / "locked"
    locked.mkdir()
    real = os.access
    monkeypatch.setattr(config.os, "access",
                        lambda p, mode: False if Path(p) == locked else real(p, mode))
    quick_cfg["results_dir"] = str(locked / "deeper" / "results")
    msg = _check_fails(quick_cfg, "results_dir")
    assert f"{locked} is not writable" in msg


def test_results_dir_inside_a_writable_folder_passes(quick_cfg, tmp_path):
    quick_cfg["results_dir"] = str(tmp_path / "new" / "results")
    config.check(quick_cfg)
    assert config.check_results_dir("results/quick") == paths.ROOT / "results" / "quick"


def _snakemake(*args, timeout=600):
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=paths.ROOT, env=env,
                          capture_output=True, text=True, timeout=timeout)


def test_workflow_start_names_the_bad_key(tmp_path, quick_cfg):
    quick_cfg["results_dir"] = str(tmp_path / "results")
    quick_cfg["linear"]["sample_rate_hz"] = 1.0
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(quick_cfg))
    proc = _snakemake("-n", f"--configfile={bad}")
    assert proc.returncode != 0
    assert "linear.sample_rate_hz: 1 Hz is not above twice" in proc.stdout + proc.stderr


# --------------------------------------------------------------------------------------------
# Dry runs against the finished quick-profile run
# --------------------------------------------------------------------------------------------

def planned(results: Path, cfg: dict, tmp_path: Path) -> dict[str, set[str]]:
    """Rule -> reasons of the jobs ``snakemake -n`` plans for ``cfg`` (a modified copy of the
    quick config, results_dir = the finished run), from the dry run's closing "Reasons:" summary
    (the per-job lines show the rules' messages, not their names)."""
    cfg = dict(cfg, results_dir=str(results))
    path = tmp_path / f"config_{time.monotonic_ns()}.yaml"
    path.write_text(yaml.safe_dump(cfg))
    proc = _snakemake("-n", "-j1", f"--configfile={path}")
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out
    jobs: dict[str, set[str]] = {}
    if "Nothing to be done" in out:
        return jobs
    summary = out.rsplit("\nReasons:", 1)[1].splitlines()[1:]
    reason = None
    for line in summary:
        if line.startswith("        ") and reason:
            for rule in line.strip().split(", "):
                jobs.setdefault(rule, set()).add(reason)
        elif line.startswith("    ") and line.rstrip().endswith(":"):
            reason = line.strip().rstrip(":").lower()
        elif line.strip() and not line.startswith("    "):
            break
    assert jobs, out
    return jobs


DEPENDENT = "input files updated by another job"


def _direct(jobs: dict[str, set[str]], reason: str) -> set[str]:
    return {r for r, why in jobs.items() if any(reason in w for w in why)}


def _only_dependents(jobs, direct):
    others = {r: why for r, why in jobs.items() if r not in direct}
    assert all(why == {DEPENDENT} for why in others.values()), others


@pytest.fixture(scope="module")
def baseline(quick_workflow):
    if quick_workflow.returncode != 0:
        pytest.fail("the quick workflow failed:\n" + quick_workflow.log[-3000:])
    cfg = config.merge(config.read_yaml(paths.CONFIG / "config.yaml"),
                       config.read_yaml(paths.CONFIG / "quick.yaml"))
    return quick_workflow.results, cfg


def test_unchanged_config_plans_nothing(baseline, tmp_path):
    results, cfg = baseline
    assert planned(results, cfg, tmp_path) == {}


# (family, dotted key, new value, rules reading the value, rules that must not run at all)
SECTION2 = {"section2_table_d_1", "section2_disturbance", "section2_numbers",
            "figures_section2", "section2_report"}
LINEAR = {"linear_eigen", "linear_ps", "linear_time_la", "linear_time_ln", "linear_rd",
          "linear_table_4_1", "linear_report"}
NONLINEAR = {"nonlinear_codegen_variant", "nonlinear_codegen", "nonlinear_calibration",
             "nonlinear_linearisation",
             "nonlinear_time_chunk", "nonlinear_time", "nonlinear_rd", "nonlinear_report",
             "figures_nonlinear"}
MOCAP = {"mocap_runs", "mocap_extract", "validation_tables", "validation_report",
         "validation_figure_data", "figures_validation"}
CHANGES = [
    ("section2", "section2.cadence_rpm", 55.0,
     {"section2_disturbance", "section2_numbers"},
     LINEAR | NONLINEAR | MOCAP | {"section2_table_d_1"}),
    ("section2", "section2.harmonics", 4, {"section2_table_d_1"},
     LINEAR | NONLINEAR | MOCAP | {"section2_disturbance", "section2_numbers"}),
    ("linear", "linear.time_speed_step_m_s", 2.5,
     {"linear_time_la", "linear_time_ln", "nonlinear_time_chunk", "nonlinear_time",
      "nonlinear_rd", "periodic_map"},
     SECTION2 | MOCAP | {"linear_eigen", "linear_ps", "linear_table_4_1", "nonlinear_codegen",
                         "nonlinear_codegen_variant", "nonlinear_linearisation"}),
    ("linear", "linear.eigen_speed_step_m_s", 0.04,
     {"linear_eigen", "linear_report", "nonlinear_linearisation", "linear_figure_data",
      "own_bicycle_resonance"},
     SECTION2 | MOCAP | {"linear_ps", "linear_time_la", "linear_time_ln", "linear_rd",
                         "nonlinear_time_chunk", "nonlinear_time"}),
    ("linear", "linear.rtol", 1e-4, {"linear_time_ln"},
     SECTION2 | MOCAP | NONLINEAR | {"linear_eigen", "linear_ps", "linear_time_la",
                                     "linear_table_4_1"}),
    ("nonlinear", "nonlinear.rtol", 1e-7, {"nonlinear_time_chunk", "nonlinear_time"},
     SECTION2 | MOCAP | LINEAR - {"linear_report"} | {"nonlinear_linearisation",
                                                       "nonlinear_codegen_variant"}),
    ("mocap", "mocap.angle_lowpass_hz", 10.0, {"mocap_extract"},
     SECTION2 | LINEAR | NONLINEAR | {"mocap_runs"}),
    ("mocap", "mocap.marker_noise_m", 0.0002, {"mocap_runs"},
     SECTION2 | LINEAR | NONLINEAR),
    ("report", "profile", "thesis", {"linear_report"},
     SECTION2 | MOCAP | NONLINEAR | LINEAR - {"linear_report"}),
]


@pytest.mark.parametrize("family, key, value, params_changed, untouched", CHANGES,
                         ids=[c[1] for c in CHANGES])
def test_config_change_plans_exactly_its_rules(baseline, tmp_path, family, key, value,
                                               params_changed, untouched):
    """Every rule reading the value is planned; those not already planned as a dependent say
    "params have changed" (Snakemake checks params only of jobs not yet planned), and so does
    write_config (its params are the whole config); no other rule is planned for a params
    change, every other planned job is a dependent, and the other families' rules do not run.
    The book (family "book") is a dependent of every change."""
    results, cfg = baseline
    cfg = copy.deepcopy(cfg)
    *path, last = key.split(".")
    target = cfg
    for k in path:
        target = target[k]
    target[last] = value
    jobs = planned(results, cfg, tmp_path)
    direct = _direct(jobs, "params have changed")
    print(f"{family}: {key} -> {value!r}: planned {sorted(jobs)}; params changed: "
          f"{sorted(direct)}")
    assert "write_config" in direct and direct <= params_changed | {"write_config"}
    assert params_changed <= set(jobs)
    _only_dependents(jobs, direct)
    assert not set(jobs) & untouched
    assert {"book", "all"} <= set(jobs)


def _touched(results, cfg, tmp_path, rel):
    """Plan after editing ``rel`` (one newline appended: valid in every format; Snakemake
    compares input checksums, so a touch alone reruns nothing). Content and mtime restored."""
    f = paths.ROOT / rel
    st, original = f.stat(), f.read_bytes()
    try:
        f.write_bytes(original + b"\n")
        os.utime(f, (st.st_atime, time.time() + 5))
        return planned(results, cfg, tmp_path)
    finally:
        f.write_bytes(original)
        os.utime(f, (st.st_atime, st.st_mtime))


def _assert_users_rerun(jobs, direct, expected):
    """Every user of the edited file is planned; those not already planned as dependents say
    "updated input files" (Snakemake does not list further reasons of a job already planned),
    no other rule does, and every other planned job is a dependent."""
    assert direct and direct <= expected, (direct, expected)
    assert expected <= set(jobs), expected - set(jobs)
    _only_dependents(jobs, direct)


def _users(rel, scripts=RULE_SCRIPTS):
    return {s.name for s in scripts if rel in dependencies.code_inputs(s, root=paths.ROOT)}


# rule script -> rules running it (several rules share a script)
RULES_OF = {
    "linear_time.py": {"linear_time_la", "linear_time_ln"},
    "figures.py": {"figures_section2", "figures_linear_overview", "figures_linear_rd",
                   "figures_linear_time_hs_cf", "figures_linear_time_hr_cr",
                   "figures_linear_spectra", "figures_nonlinear", "figures_validation"},
}


def _rules(script_names):
    return set().union(*(RULES_OF.get(s, {s.removesuffix(".py")}) for s in script_names))


@pytest.mark.parametrize("rel, expected", [
    # hand-checked: BicycleParameters' files are read by nonlinear/bicycle_data.py, which the
    # calibration, the linearisation, the NT/NP sweeps and the periodic orbits import, and by
    # own_bicycle.py (Jason rides the "Your own bicycle" example), and nothing else
    ("data/parameters/bicycleparameters/riders/Jason/RawData/JasonYeadonMeas.txt",
     {"nonlinear_calibration", "nonlinear_linearisation", "nonlinear_time_chunk",
      "nonlinear_time", "own_bicycle_resonance", "periodic_map", "periodic_map_subgrid",
      "periodic_branch", "periodic_tables"}),
    # the C driver: every rule compiling or loading the non-linear model
    ("src/pedalrepro/csrc/model_rhs.h",
     {"nonlinear_codegen_variant", "nonlinear_calibration", "nonlinear_linearisation",
      "nonlinear_time_chunk", "nonlinear_time", "periodic_map", "periodic_map_subgrid",
      "periodic_branch", "periodic_tables"}),
    # the figure style: every figure rule, the closed-loop and own-bicycle rules (they draw
    # their figures too) and the book's notebook jobs (notebooks draw figures), then the book
    ("src/pedalrepro/pedalrepro.mplstyle",
     {"figures_section2", "figures_linear_overview", "figures_linear_rd",
      "figures_linear_time_hs_cf", "figures_linear_time_hr_cr", "figures_linear_spectra",
      "figures_nonlinear", "figures_validation", "figures_periodic",
      "closed_loop_figures", "own_bicycle_resonance", "book_notebook", "book"}),
    # its own job (rule book_notebook), then the book as its dependent
    ("notebooks/02_pedalling_disturbance.ipynb", {"book_notebook", "book"}),
    # the run list: the mocap rules, Table 4.1's model column, the figure-data rule of chapter 3
    # (pedalrepro.figdata imports pedalrepro.validation for its Figs 4.2-4.10 part) and the
    # spectra rule (pedalrepro.mocap.fetch imports the run list's reader)
    ("data/parameters/validation_runs.yaml",
     {"linear_table_4_1", "mocap_runs", "mocap_extract", "validation_tables",
      "validation_report", "linear_figure_data", "closed_loop_spectra"}),
])
def test_touched_file_reruns_exactly_its_users(baseline, tmp_path, rel, expected):
    results, cfg = baseline
    jobs = _touched(results, cfg, tmp_path, rel)
    direct = _direct(jobs, "updated input files")
    print(f"touch {rel}: planned {sorted(jobs)}; updated input: {sorted(direct)}")
    _assert_users_rerun(jobs, direct, expected)


# files some rules also name as inputs (their scripts read them through snakemake.input)
NAMED_INPUT = {"data/published/meijaard2007.yaml": {"linear_report", "nonlinear_linearisation",
                                                    "nonlinear_report"}}


@pytest.mark.parametrize("rel", ["src/pedalrepro/gears.py", "src/pedalrepro/spectral.py",
                                 "data/parameters/stratos.yaml",
                                 "data/published/meijaard2007.yaml"])
def test_touched_module_or_parameter_file_reruns_its_import_closure(baseline, tmp_path, rel):
    """The rules planned because of the touched file are those whose script (for the book's
    notebook jobs: also the notebooks and the drawing modules) reaches it through imports and
    declarations; the rest are dependents."""
    results, cfg = baseline
    jobs = _touched(results, cfg, tmp_path, rel)
    direct = _direct(jobs, "updated input files")
    expected = _rules(_users(rel)) | NAMED_INPUT.get(rel, set())
    drawing = [paths.ROOT / src for g in FIGURE_REGISTRY.groups()
               for src in FIGURE_REGISTRY.code_sources(g)]
    if rel in dependencies.code_inputs(*NOTEBOOKS, *drawing, root=paths.ROOT):
        expected |= {"book_notebook", "book"}  # the notebooks' jobs, the book as a dependent
    if rel.startswith("src/pedalrepro/") and rel.endswith(".py"):  # the API page
        expected.add("book")
    print(f"touch {rel}: planned {sorted(jobs)}; updated input: {sorted(direct)}")
    _assert_users_rerun(jobs, direct, expected)


def figure_group_code(group: str) -> list[str]:
    """The code inputs rules/figures.smk gives figure group ``group``'s rule (the same
    computation): scripts/figures.py (the registry, the page style) and the closure of the
    group's own drawing modules."""
    return sorted(set(dependencies.code_inputs(paths.ROOT / "rules/scripts/figures.py",
                                               root=paths.ROOT))
                  | set(dependencies.code_inputs(*FIGURE_REGISTRY.code_sources(group),
                                                 root=paths.ROOT)))


def test_every_file_a_rule_reads_is_its_input(quick_workflow):
    """The end-to-end run recorded, per process, the data files and package resources it opened
    and the pedalrepro modules it loaded (PEDALREPRO_TRACE, tests/trace/sitecustomize.py). Each
    must be an input of the rule that ran (code_inputs of its script; for a figure group, of the
    script and the group's drawing modules, :func:`figure_group_code`; for the book's notebook
    kernels, of the notebooks): a module reading a file no rule declares fails here."""
    import json

    if quick_workflow.returncode != 0:
        pytest.fail("the quick workflow failed:\n" + quick_workflow.log[-3000:])
    scripts = {s.name: s for s in RULE_SCRIPTS}
    seen = set()
    for trace in sorted(quick_workflow.trace.glob("*.json")):
        rec = json.loads(trace.read_text())
        name = Path(rec["argv0"]).name
        if name.startswith("tmp") and name.split(".", 1)[-1] == "figures.py":
            script = "figures.py"  # a figure group: known by the drawing modules it loaded
            inputs = set().union(*(figure_group_code(g) for g in FIGURE_REGISTRY.groups()
                                   if set(FIGURE_REGISTRY.code_sources(g)) <= set(rec["modules"])))
        elif name.startswith("tmp") and name.split(".", 1)[-1] in scripts:
            script = name.split(".", 1)[-1]
            inputs = set(dependencies.code_inputs(scripts[script], root=paths.ROOT))
        elif "ipykernel" in rec["argv0"]:
            script = "notebooks"
            # figures.draw(id) imports the figure's drawing module by the registry's name for
            # it (no import statement to follow): the notebooks' code is their closure plus the
            # drawing modules' (the book rule has every package module as input anyway, for the
            # API page)
            drawing = [src for g in FIGURE_REGISTRY.groups()
                       for src in FIGURE_REGISTRY.code_sources(g)]
            inputs = set(dependencies.code_inputs(*NOTEBOOKS, *(paths.ROOT / d for d in drawing),
                                                  root=paths.ROOT))
        else:
            continue  # snakemake itself (it imports pedalrepro to parse the rules)
        seen.add(script)
        # a file a rule names as input (read through snakemake.input) is an input too
        missing = {f for f in set(rec["files"]) - inputs if f'"{f}"' not in SMK_TEXT}
        assert not missing, f"{script} read {sorted(missing)}, not among its inputs"
        missing = set(rec["modules"]) - inputs
        assert not missing, f"{script} imported {sorted(missing)}, not in its closure"
    missing = (set(scripts) | {"notebooks"}) - seen
    assert not missing, f"no trace of {sorted(missing)}"


# --------------------------------------------------------------------------------------------
# Change tracking per figure group
# --------------------------------------------------------------------------------------------

FIGURE_RULES = {f"figures_{g}" for g in FIGURE_REGISTRY.groups()}
CLAIMS = "data/published/claims.yaml"
SECTION2_FIGURES = "src/pedalrepro/figures/section2.py"


def test_each_figure_group_depends_on_its_own_drawing_code():
    """A group's code is the registry's plus its own drawing modules' closure: the section-2
    module is the section-2 group's only, and no group reaches the report or the claims."""
    code = {g: figure_group_code(g) for g in FIGURE_REGISTRY.groups()}
    assert [g for g, files in code.items() if SECTION2_FIGURES in files] == ["section2"]
    for g, files in code.items():
        assert CLAIMS not in files and "src/pedalrepro/report.py" not in files, g
        assert "src/pedalrepro/_trace.py" not in files, g
        assert f"src/pedalrepro/figures/{g.split('_')[0]}.py" in files, g
    # the shared part is small: the drawing script, the registry, the page style, paths, the
    # time-solution reader and the package __init__ files (39 files per group before)
    shared = set.intersection(*(set(f) for f in code.values()))
    assert shared == {"rules/scripts/figures.py", "src/pedalrepro/__init__.py",
                      "src/pedalrepro/book.py",
                      "src/pedalrepro/figures/__init__.py", "src/pedalrepro/figures/page.py",
                      "src/pedalrepro/figures/registry.py", "src/pedalrepro/paths.py",
                      "src/pedalrepro/pedalrepro.mplstyle", "src/pedalrepro/timesolution.py"}


def test_claims_reach_report_rules_only():
    """Through the dependency closure: every rule script reaching claims.yaml writes report rows
    (``*_report.py``), and no figure reads a file of the report (tables/report/, the joined
    reproduction report), so editing a claim can plan no figure rule."""
    users = _users(CLAIMS)
    assert users and all(s.endswith("_report.py") for s in users), sorted(users)
    assert "validation_report.py" in users and "validation_tables.py" not in users
    for fid in FIGURE_REGISTRY.ids():
        for rel in FIGURE_REGISTRY.spec(fid).inputs.values():
            assert not rel.startswith("tables/report/") and "reproduction_report" not in rel, fid


def test_editing_claims_plans_no_figure_rule(baseline, tmp_path):
    results, cfg = baseline
    jobs = _touched(results, cfg, tmp_path, CLAIMS)
    print(f"touch {CLAIMS}: planned {sorted(jobs)}")
    assert not set(jobs) & FIGURE_RULES, sorted(set(jobs) & FIGURE_RULES)
    assert not set(jobs) & {"validation_tables", "validation_figure_data", "linear_figure_data"}
    assert {"validation_report", "reproduction_report", "book"} <= set(jobs)


def test_editing_section2_figures_plans_only_the_section2_figures(baseline, tmp_path):
    results, cfg = baseline
    jobs = _touched(results, cfg, tmp_path, SECTION2_FIGURES)
    direct = _direct(jobs, "updated input files")
    print(f"touch {SECTION2_FIGURES}: planned {sorted(jobs)}; updated input: {sorted(direct)}")
    assert set(jobs) & FIGURE_RULES == {"figures_section2"}
    # the book's notebooks import the module too (the API page documents it)
    _assert_users_rerun(jobs, direct, {"figures_section2", "book"})
