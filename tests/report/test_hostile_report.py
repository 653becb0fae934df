"""Hostile inputs to ``pedalrepro report-status``: a malformed report or one built with another
configuration is refused (exit 2, the file and the fault named) and the pin file is unchanged."""

from __future__ import annotations

import shutil

import pandas as pd
import pytest

from pedalrepro import cli, config, paths, report


@pytest.fixture()
def pin(tmp_path, monkeypatch):
    """A copy of the repository's pin file as the one ``report-status`` reads and writes."""
    copy = tmp_path / "expected_status.csv"
    shutil.copy(paths.ROOT / report.EXPECTED_STATUS_FILE, copy)
    monkeypatch.setattr(paths, "ROOT", tmp_path / "root")
    (tmp_path / "root" / "tests").mkdir(parents=True)
    target = tmp_path / "root" / report.EXPECTED_STATUS_FILE
    shutil.copy(copy, target)
    return target


def _results(tmp_path, profile_files=("quick.yaml",), **edits):
    """A results folder holding a one-row report and the configuration copy of a profile."""
    res = tmp_path / "results"
    cfg = config.load(None, *[paths.CONFIG / f for f in profile_files])
    for key, value in edits.items():
        cfg[key] = value
    config.write(cfg, res / config.COPY_NAME)
    row = report.check("nrmsd_com_z", 3.64)
    rep = report.write_rows([row], res / "tables" / "reproduction_report.csv")
    return res / "tables" / "reproduction_report.csv", rep


def _run(args, capsys):
    code = cli.main(args)
    return code, capsys.readouterr()


@pytest.mark.parametrize(("edit", "message"), [
    (lambda df: df.assign(status="almost"), "unknown status \\['almost'\\]"),
    (lambda df: pd.concat([df, df]), "repeated ids \\['nrmsd_com_z'\\]"),
    (lambda df: df.drop(columns=["note"]), "columns"),
    (lambda df: df.assign(id=""), "without an id"),
])
def test_malformed_reports_are_refused_and_the_pin_kept(tmp_path, pin, capsys, edit, message):
    path, rep = _results(tmp_path)
    edit(rep).to_csv(path, index=False)
    before = pin.read_bytes()
    code, out = _run(["report-status", str(path), "--profile", "quick", "--update"], capsys)
    assert code == 2
    assert str(path) in out.err
    assert pd.Series([out.err]).str.contains(message).item(), out.err
    assert pin.read_bytes() == before


def test_a_quick_report_cannot_write_the_thesis_column(tmp_path, pin, capsys):
    path, _ = _results(tmp_path)
    before = pin.read_bytes()
    code, out = _run(["report-status", str(path), "--profile", "thesis", "--update"], capsys)
    assert code == 2 and "built with the quick profile" in out.err
    assert pin.read_bytes() == before


def test_a_report_of_another_configuration_pins_nothing(tmp_path, pin, capsys):
    path, _ = _results(tmp_path, seed=1)
    before = pin.read_bytes()
    code, out = _run(["report-status", str(path), "--profile", "quick", "--update"], capsys)
    assert code == 2 and "neither the thesis nor the quick profile" in out.err
    assert "'seed'" in out.err
    assert pin.read_bytes() == before


def test_a_valid_quick_report_updates_only_its_column(tmp_path, pin, capsys):
    path, _ = _results(tmp_path)
    old = report.expected_status(pin)
    code, out = _run(["report-status", str(path), "--profile", "quick", "--update"], capsys)
    assert code == 0, out.err
    new = report.expected_status(pin)
    row = new[new["id"] == "nrmsd_com_z"].iloc[0]
    assert row["quick"] == report.REPRODUCED
    assert row["thesis"] == old[old["id"] == "nrmsd_com_z"].iloc[0]["thesis"]
    # the report had one row: the quick column of every other id is cleared, thesis kept
    assert (new["thesis"].to_numpy() == old.set_index("id").loc[new["id"], "thesis"]
            .to_numpy()).all()
