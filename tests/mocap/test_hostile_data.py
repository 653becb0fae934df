"""Corrupt and missing treadmill data files (issue 22, case 6).

A corrupt cached file is named with both hashes (the registry's and the file's) in every
``data_source`` mode, never reported as a network problem only; a missing one is named; the
``figshare`` failure reaches Snakemake's own output (the job's stderr), not only the job log.
No network: pooch's DOI lookup and download are replaced by a ConnectionError, as offline.
"""

from __future__ import annotations

import hashlib
import runpy
from types import SimpleNamespace

import pooch
import pytest
import requests
from mocap_data import CFG, SEED

from pedalrepro import paths
from pedalrepro.mocap import fetch, prepare, reader, synthetic


def _offline(*args, **kwargs):
    raise requests.exceptions.ConnectionError("offline (test)")


@pytest.fixture()
def offline(monkeypatch):
    monkeypatch.setattr(pooch.Pooch, "load_registry_from_doi", _offline)
    monkeypatch.setattr(pooch.Pooch, "fetch", _offline)


@pytest.fixture(scope="module")
def good_bytes(tmp_path_factory) -> bytes:
    """A stand-in run file in the published RNNN.mat layout."""
    r = next(x for x in synthetic.stand_in_runs(CFG) if x.system == "HR")
    mat, _ = synthetic.simulate_run(r, CFG, SEED, "nan")
    path = tmp_path_factory.mktemp("good") / "run.mat"
    synthetic.savemat(path, mat)
    return path.read_bytes()


@pytest.fixture()
def corrupt_cache(tmp_path, monkeypatch, good_bytes):
    """Data folder with 3045.mat whose bytes differ from its sha256 in the registry."""
    data = tmp_path / "data"
    data.mkdir()
    name = "3045.mat"
    want = hashlib.sha256(good_bytes).hexdigest()
    bad = bytearray(good_bytes)
    bad[-10] ^= 0xFF
    (data / name).write_bytes(bytes(bad))
    got = hashlib.sha256(bytes(bad)).hexdigest()
    reg = tmp_path / "registry.txt"
    fetch.write_registry({name: f"sha256:{want}"}, reg)
    monkeypatch.setenv(fetch.ENV, str(data))
    return SimpleNamespace(pup=fetch.make_pooch(registry=reg), name=name, want=want, got=got,
                           data=data)


def _names_both(msg: str, c) -> None:
    assert str(c.data / c.name) in msg, msg
    assert c.want in msg and c.got in msg, msg


def test_corrupt_cached_file_auto_names_both_hashes(offline, corrupt_cache):
    """It was "figshare unreachable" only; auto still falls back, with the file in the reason."""
    source, reason = fetch.resolve_source("auto", corrupt_cache.pup)
    assert source == "synthetic"
    _names_both(reason, corrupt_cache)
    assert "corrupt" in reason


def test_corrupt_cached_file_figshare_names_both_hashes(offline, corrupt_cache):
    with pytest.raises(fetch.CorruptDataError) as info:
        fetch.resolve_source("figshare", corrupt_cache.pup)
    _names_both(str(info.value), corrupt_cache)
    # still a DataUnavailableError (callers catching it keep working) and a HashMismatchError
    assert isinstance(info.value, fetch.DataUnavailableError)
    assert isinstance(info.value, fetch.HashMismatchError)
    assert (corrupt_cache.data / corrupt_cache.name).exists()  # resolving removes nothing


def test_prepare_runs_figshare_keeps_the_hashes(offline, corrupt_cache, monkeypatch, tmp_path):
    monkeypatch.setattr(fetch, "make_pooch", lambda *a, **k: corrupt_cache.pup)
    with pytest.raises(fetch.HashMismatchError) as info:
        prepare.prepare_runs("figshare", tmp_path / "runs", CFG, SEED)
    _names_both(str(info.value), corrupt_cache)


def test_corrupt_file_that_cannot_be_fetched_again_names_both_hashes(offline, corrupt_cache):
    events: list[str] = []
    with pytest.raises(fetch.CorruptDataError) as info:
        fetch.fetch(corrupt_cache.name, corrupt_cache.pup, progressbar=False, events=events)
    _names_both(str(info.value), corrupt_cache)
    assert "cannot be downloaded again" in str(info.value)
    _names_both(events[0], corrupt_cache)


def test_corrupt_public_subset_file_is_named_in_auto(offline, tmp_path, monkeypatch,
                                                     good_bytes):
    """The public subset (auto mode): a corrupt 3045_X.xlsx is left out with both hashes."""
    data = tmp_path / "data"
    data.mkdir()
    (data / "3045_X.xlsx").write_bytes(b"not the published file")
    got = hashlib.sha256(b"not the published file").hexdigest()
    monkeypatch.setenv(fetch.ENV, str(data))
    pup = fetch.make_public_pooch()
    want = pup.registry["3045_X.xlsx"].removeprefix("sha256:")
    events: list[str] = []
    files = fetch.public_files(pup, progressbar=False, events=events)
    assert "3045_X.xlsx" not in files
    note = next(e for e in events if e.startswith("3045_X.xlsx not available"))
    assert want in note and got in note and str(data / "3045_X.xlsx") in note


def test_missing_files_are_named_in_figshare_mode(offline, tmp_path, monkeypatch):
    monkeypatch.setenv(fetch.ENV, str(tmp_path))
    reg = tmp_path / "registry.txt"
    fetch.write_registry({"3082.mat": "md5:" + "0" * 32, "3083.mat": "md5:" + "1" * 32}, reg)
    pup = fetch.make_pooch(registry=reg)
    with pytest.raises(fetch.DataUnavailableError,
                       match=r"Missing from .*: 3082.mat, 3083.mat \(2 of rider 3"):
        fetch.resolve_source("figshare", pup)
    assert fetch.resolve_source("auto", pup)[0] == "synthetic"


def test_verified_cache_is_used_offline(offline, corrupt_cache, good_bytes):
    """The equivalent valid input: the published bytes in place -> figshare, offline."""
    (corrupt_cache.data / corrupt_cache.name).write_bytes(good_bytes)
    assert fetch.resolve_source("figshare", corrupt_cache.pup) == (
        "figshare", "all registry run files cached and verified")


@pytest.mark.parametrize("content", [b"", b"\x00" * 100, b"MATLAB 5.0 MAT-file garbage"])
def test_unreadable_run_file_is_named(tmp_path, content):
    bad = tmp_path / "3045.mat"
    bad.write_bytes(content)
    with pytest.raises(reader.MocapFileError, match="3045.mat"):
        reader.read_run(bad)


def test_figshare_failure_reaches_snakemake_output(tmp_path, monkeypatch, capfd):
    """rules/scripts/mocap_runs.py prints the reason on the job's own stderr (which Snakemake
    shows) as well as into the log, and exits 1 (no traceback)."""
    def refuse(*a, **k):
        raise fetch.CorruptDataError("3045.mat: sha256 hash aaa does not match (bbb)")

    monkeypatch.setattr(prepare, "prepare_runs", refuse)
    log = tmp_path / "mocap_runs.log"
    snake = SimpleNamespace(log=[str(log)], params=SimpleNamespace(
        data_source="figshare", mocap={}, seed=SEED),
        output=SimpleNamespace(runs=str(tmp_path / "runs"), source=str(tmp_path / "s.json")))
    import sys
    monkeypatch.setattr(sys, "stderr", sys.stderr)  # the script replaces it; restored after
    with pytest.raises(SystemExit) as info:
        runpy.run_path(str(paths.ROOT / "rules" / "scripts" / "mocap_runs.py"),
                       init_globals={"snakemake": snake})
    assert info.value.code == 1
    sys.stderr.close()
    shown = capfd.readouterr().err
    assert "Error in rule mocap_runs: 3045.mat: sha256 hash aaa does not match (bbb)" in shown
    assert "3045.mat: sha256 hash aaa" in log.read_text()
    assert not (tmp_path / "s.json").exists()
