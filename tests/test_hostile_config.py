"""Hostile configurations (issue 22): every value the schema accepts gives a correct result or a
clear refusal naming the key, and no results folder can overwrite a file of the repository.

Each case asserts its outcome: refused with the key (and the offending value or path) named, or
accepted with the same result as an equivalent valid input. Fast: the validator
(``config.validate`` + ``config.check``) is called directly; one workflow start (``snakemake``,
refused at parse time, no job runs) checks that ``results_dir: config`` leaves config/ unchanged.
"""

from __future__ import annotations

import copy
import hashlib
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from pedalrepro import config, paths


@pytest.fixture()
def cfg():
    """The quick profile (config/config.yaml + config/quick.yaml), a fresh copy per test."""
    return copy.deepcopy(config.merge(config.read_yaml(paths.CONFIG / "config.yaml"),
                                      config.read_yaml(paths.CONFIG / "quick.yaml")))


def refused(cfg, key, *fragments):
    """``config.validate`` + ``config.check`` refuse ``cfg`` with ``key`` (and each fragment)
    named; returns the message."""
    with pytest.raises(config.ConfigError) as info:
        config.validate(cfg)
        config.check(cfg)
    msg = str(info.value)
    assert re.search(rf"(^|\s){re.escape(key)}[:\s]", msg), msg
    for f in fragments:
        assert f in msg, msg
    return msg


def accepted(cfg):
    config.validate(cfg)
    config.check(cfg)


# --------------------------------------------------------------------------------------------
# results_dir: never inside or on a source of the repository (issue 22, case 1)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("folder", ["config", "config/", "./config", "src", "src/pedalrepro",
                                    "data", "data/published", "tests", "rules", "notebooks",
                                    "book", "book/_build", "scripts", "profiles/slurm",
                                    "README.md", "Snakefile", ".git", ".snakemake",
                                    "results/../config", str(paths.ROOT / "src")])
def test_results_dir_inside_a_source_is_refused_with_the_path(cfg, folder):
    cfg["results_dir"] = folder
    msg = refused(cfg, "results_dir", repr(folder))
    first = Path(folder).parts[0] if not Path(folder).is_absolute() else "src"
    first = "config" if first in (".", "results") else first
    assert str(paths.ROOT / first) in msg


@pytest.mark.parametrize("folder", ["..", str(paths.ROOT.parent)])
def test_results_dir_holding_the_repository_is_refused(cfg, folder):
    cfg["results_dir"] = folder
    refused(cfg, "results_dir", "holds the repository")


def test_results_dir_symlink_into_a_source_is_refused(cfg, tmp_path):
    link = tmp_path / "looks_harmless"
    link.symlink_to(paths.CONFIG)
    cfg["results_dir"] = str(link)
    refused(cfg, "results_dir", str(paths.CONFIG))


@pytest.mark.parametrize("folder", ["results", "results/quick", "results/config",
                                    "results/my run"])
def test_results_dir_in_results_is_accepted(cfg, folder):
    cfg["results_dir"] = folder
    accepted(cfg)
    assert config.check_results_dir(folder) == (paths.ROOT / folder).resolve()


def test_the_config_copy_has_a_name_no_source_file_has():
    tracked = subprocess.run(["git", "-C", str(paths.ROOT), "ls-files"], capture_output=True,
                             text=True, check=True).stdout.split()
    assert config.COPY_NAME not in {Path(f).name for f in tracked}
    smk = (paths.ROOT / "rules" / "common.smk").read_text()
    assert 'CONFIG_COPY = f"{R}/{pconfig.COPY_NAME}"' in smk


def test_config_write_refuses_a_source_path(tmp_path):
    target = paths.CONFIG / "config.yaml"
    before = target.read_bytes()
    with pytest.raises(config.ConfigError, match=re.escape(str(target))):
        config.write({"results_dir": "config"}, target)
    assert target.read_bytes() == before
    out = config.write({"a": 1}, tmp_path / config.COPY_NAME)
    assert config.read_yaml(out) == {"a": 1}
    assert config.results_config(tmp_path) == {"a": 1}


def _tree_digest(folder: Path) -> dict[str, str]:
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def test_workflow_with_results_dir_config_is_refused_and_config_unchanged(tmp_path):
    """The issue's command: ``snakemake -j1 --configfile config/quick.yaml rd.yaml`` with
    ``results_dir: config`` overwrote config/config.yaml (rc 0); now it stops at parse time
    naming the key and the folder, and config/ is byte for byte the same."""
    rd = tmp_path / "rd.yaml"
    rd.write_text("results_dir: config\n")
    before = _tree_digest(paths.CONFIG)
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-j1", "--configfile",
                           "config/quick.yaml", str(rd), "--", "config/config.yaml"],
                          cwd=paths.ROOT, env=env, capture_output=True, text=True, timeout=300)
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0, out
    assert "results_dir: 'config' resolves to" in out, out
    assert _tree_digest(paths.CONFIG) == before
    assert not (paths.CONFIG / config.COPY_NAME).exists()


# --------------------------------------------------------------------------------------------
# Lists and ranges (issue 22, cases 2 and 8)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("key, value, repeated", [
    ("linear.harmonics", [1, 1, 3, 5], "1"),   # doubled every time-domain amplitude (rc 0)
    ("linear.gear_ratios", [1, 2, 2.0, 4], "2"),
    ("mocap.stand_in_gear_ratios", [1.6, 1.6], "1.6"),
    ("periodic.methods", ["NT", "NT"], "NT"),
    ("periodic.fine_methods", ["NT", "NT"], "NT"),
    ("periodic.continuation_methods", ["NP", "NP"], "NP"),
    ("periodic.continuation_torque_scales", [1.0, 1.0], "1.0"),
])
def test_repeated_list_items_are_refused(cfg, key, value, repeated):
    section, name = key.split(".")
    cfg[section][name] = value
    msg = refused(cfg, key, "non-unique")
    # the cross-key rule names the repeated item too (for a config reaching check() directly)
    with pytest.raises(config.ConfigError, match=rf"{re.escape(key)}: .* repeats {repeated}"):
        config.check(cfg)
    assert msg


@pytest.mark.parametrize("key, value, fixed_by", [
    ("linear.models", ["benchmark", "HR"], "pedalrepro.params.LINEAR_MODELS"),
    ("nonlinear.models", ["HR"], "pedalrepro.params.MODELS"),
])
def test_model_lists_are_refused_with_the_reason(cfg, key, value, fixed_by):
    """The model lists left the configuration (issue 26, part 4): the thesis fixes them and every
    figure and notebook covers all of them. An old config still setting one is refused, naming
    the key, why, and where another bicycle goes, not with the schema's "unknown key"."""
    section, name = key.split(".")
    cfg[section][name] = value
    msg = refused(cfg, key, "retired keys (refused, not ignored)",
                  f"{key}: the {'non-' if section == 'nonlinear' else ''}linear models are fixed "
                  f"by the thesis ({fixed_by}", "pedalrepro.params.MODELS", "remove the key",
                  "pedalrepro.own_bicycle (rule own_bicycle_resonance")
    assert "Additional properties" not in msg, msg
    # the shipped profiles and the schema no longer have the key
    for f in ("config.yaml", "quick.yaml", "schema.yaml"):
        text = (paths.CONFIG / f).read_text()
        assert not re.search(rf"^\s+{name}:", text, re.M), f


@pytest.mark.parametrize("value", [[3, 1, 5], [3, 5], [1, 5, 3]])
def test_harmonics_start_at_the_cadence_and_increase(cfg, value):
    """The first harmonic is read as the amplitude at the cadence (evaluation, Fig 3.35)."""
    cfg["linear"]["harmonics"] = value
    refused(cfg, "linear.harmonics", "start at 1")


@pytest.mark.parametrize("value", [[1], [1, 3], [1, 3, 5, 7]])
def test_valid_harmonics_are_accepted(cfg, value):
    cfg["linear"]["harmonics"] = value
    accepted(cfg)


@pytest.mark.parametrize("value", [[10.0, 2.0], [5.0, 5.0]])
def test_continuation_range_must_increase(cfg, value):
    """[10, 2] emptied the branch's stable range, [5, 5] gave a 2-point branch with a NaN
    tangent; both ran with rc 0."""
    cfg["periodic"]["continuation_speed_m_s"] = value
    refused(cfg, "periodic.continuation_speed_m_s", "not an increasing range")


@pytest.mark.parametrize("key, value", [
    ("linear.normal_cycling_speed_kmh", [22.0, 14.0]),
    ("linear.normal_cycling_cadence_rpm", [60.0, 60.0]),
])
def test_normal_cycling_ranges_must_increase(cfg, key, value):
    section, name = key.split(".")
    cfg[section][name] = value
    refused(cfg, key, "not an increasing range")


@pytest.mark.parametrize("step, maximum", config.PERIODIC_STEP_MAXIMA)
def test_fine_grid_step_below_its_maximum(cfg, step, maximum):
    """A step above its maximum gave a one-point map (rc 0)."""
    cfg["periodic"][step] = cfg["periodic"][maximum] * 1.5
    refused(cfg, f"periodic.{step}", f"not below periodic.{maximum}")
    cfg["periodic"][step] = cfg["periodic"][maximum] / 4
    accepted(cfg)


@pytest.mark.parametrize("step, maximum", config.STEP_MAXIMA)
def test_linear_grid_step_above_its_maximum(cfg, step, maximum):
    cfg["linear"][step] = cfg["linear"][maximum] * 2
    refused(cfg, f"linear.{step}", f"not below linear.{maximum}")


@pytest.mark.parametrize("key, value, count", [
    ("linear.eigen_speed_step_m_s", 1e-9, "1e+10 points"),  # a 74.5 GiB MemoryError in a job
    ("linear.ps_speed_step_m_s", 1e-4, "2.6e+06 points"),  # 100001 speeds x 26 cadences
    ("linear.time_omega_step_rad_s", 1e-5, "7.54e+06 points"),
    ("periodic.fine_omega_step_rad_s", 1e-6, "7.54e+07 points"),
    ("linear.eigen_speed_step_m_s", 5e-324, "inf points"),   # max / step overflows
])
def test_grid_point_cap_gives_the_count(cfg, key, value, count):
    section, name = key.split(".")
    cfg[section][name] = value
    if name.startswith("time_omega"):
        cfg["linear"]["duration_s"] = 3600.0  # one period of the slowest cadence must fit
        cfg["linear"]["sample_rate_hz"] = 100.0
    refused(cfg, key, count, "above the cap")


def test_grid_point_count_equals_the_grid_the_rules_build(cfg):
    """The cap counts what pedalrepro.response.grid builds (0:step:max, Matlab style)."""
    from pedalrepro import response
    for step, maximum in [(0.01, 10.0), (0.124, 4 * 3.141592653589793), (0.4, 10.0),
                          (0.3, 1.0), (2.0, 10.0)]:
        assert config.grid_count(step, maximum) == len(response.grid(step, maximum))


def test_time_samples_cap(cfg):
    cfg["linear"]["duration_s"] = 3600.0
    cfg["linear"]["sample_rate_hz"] = 1000.0
    refused(cfg, "linear.sample_rate_hz", "3.6e+06 samples", "above the cap")


@pytest.mark.parametrize("chunks", [7, 64])
def test_chunks_above_the_number_of_speeds_are_refused(cfg, chunks):
    """Quick time grid 0:2:10 = 6 speeds: 64 chunks created 58 empty sweep jobs (rc 0)."""
    cfg["nonlinear"]["chunks"] = chunks
    refused(cfg, "nonlinear.chunks", f"{chunks} sweep jobs", "the 6 speeds")


def test_chunks_up_to_the_number_of_speeds_are_accepted(cfg):
    cfg["nonlinear"]["chunks"] = 6
    accepted(cfg)


@pytest.mark.parametrize("key", ["linear.rtol", "mocap.duration_s", "periodic.continuation_ds",
                                 "section2.cadence_rpm", "linear.reference_speed_m_s"])
@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_values_are_refused(cfg, key, value):
    section, name = key.split(".")
    cfg[section][name] = value
    with pytest.raises(config.ConfigError, match=re.escape(key)):
        config.validate(cfg)
        config.check(cfg)


def test_non_finite_list_item_is_refused_with_its_index(cfg):
    cfg["periodic"]["continuation_speed_m_s"] = [2.0, float("nan")]
    with pytest.raises(config.ConfigError, match=re.escape("periodic.continuation_speed_m_s[1]")):
        config.check(cfg)


def test_schema_errors_name_the_key_dotted(cfg):
    cfg["linear"]["harmonics"] = [1, 0]
    msg = refused(cfg, "linear.harmonics[1]", "less than the minimum")
    assert "linear/harmonics" not in msg


def test_workflow_start_names_the_repeated_harmonic(tmp_path):
    """The workflow's own validation (rules/common.smk) gives the same dotted key."""
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({"results_dir": str(tmp_path / "r"),
                                   "linear": {"harmonics": [1, 1, 3, 5]}}))
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-n", "--configfile",
                           "config/quick.yaml", str(bad)], cwd=paths.ROOT, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode != 0
    assert "linear.harmonics: [1, 1, 3, 5] has non-unique elements" in proc.stdout + proc.stderr
    assert not (tmp_path / "r").exists()


def test_the_shipped_profiles_pass():
    for extra in ((), ("config/quick.yaml",)):
        cfg = config.load(None, *(paths.ROOT / e for e in extra))
        assert cfg["linear"]["harmonics"] == [1, 3, 5]


# --------------------------------------------------------------------------------------------
# Cases that already held before issue 22 (kept so that they keep holding)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("folder", ["/", "/usr", "/tmp", "~", ".", ""])
def test_system_folders_home_and_root_are_refused(cfg, folder):
    cfg["results_dir"] = folder
    refused(cfg, "results_dir")


def test_trailing_slash_is_the_same_folder(cfg):
    """An equivalent spelling gives the same results folder."""
    assert config.check_results_dir("results/quick/") == config.check_results_dir("results/quick")
    assert config.check_results_dir("./results/quick") == config.check_results_dir("results/quick")


@pytest.mark.parametrize("section, key, value, fragment", [
    ("linear", "sample_rate_hz", 1.0, "Nyquist"),
    ("linear", "rtol", "1e-3", "is not of type 'number'"),
    ("linear", "harmonics", [1, 0], "less than the minimum of 1"),
    ("linear", "extra_key", 1, "Additional properties are not allowed"),
    ("nonlinear", "chunks", 0, "less than the minimum of 1"),
    ("nonlinear", "method", "Euler", "'Euler' is not one of"),
    ("mocap", "angle_lowpass_hz", -1.0, "less than the minimum of 0"),
    ("periodic", "continuation_speed_m_s", [2.0], "is too short"),
])
def test_values_outside_the_schema_are_refused(cfg, section, key, value, fragment):
    cfg[section][key] = value
    with pytest.raises(config.ConfigError) as info:
        config.validate(cfg)
        config.check(cfg)
    assert section in str(info.value) and fragment in str(info.value), str(info.value)
