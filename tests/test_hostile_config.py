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
