"""The online path on a real HTTP server (127.0.0.1, a free port), no internet needed.

A local ``http.server`` serves run files: synthetic ``RNNN.mat`` in the published format (as
figshare would, the DOI resolution mocked to point at the server) and the real public subset
(the base URL pointed at the server). Fetch, verify and extract run end to end, including a
file served corrupt once (reported, removed, fetched again), a download interrupted once
(resumed with an HTTP Range request), the empty shipped registry (file list and checksums from
the DOI at run time, only rider 3's runs fetched) and the fallbacks of ``auto``.
"""

from __future__ import annotations

import hashlib
import io
import re
import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import pooch
import pytest
import requests
import scipy.io
from mocap_data import CFG, SEED, copy_real_subset

from pedalrepro.mocap import fetch, prepare, runs, synthetic


class Served:
    """What the server holds and how it misbehaves (each at most once per name)."""

    def __init__(self, files: dict[str, bytes]):
        self.files = files
        self.corrupt_once: set[str] = set()
        self.interrupt_once: set[str] = set()
        self.missing: set[str] = set()
        self.requests: list[tuple[str, str | None]] = []


def _handler(served: Served):
    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args):  # quiet
            pass

        def do_GET(self):
            name = self.path.lstrip("/")
            rng = self.headers.get("Range")
            served.requests.append((name, rng))
            if name not in served.files or name in served.missing:
                self.send_error(404)
                return
            data = served.files[name]
            if name in served.corrupt_once:
                served.corrupt_once.discard(name)
                data = bytes(b ^ 0xFF if i == len(data) // 2 else b for i, b in enumerate(data))
            start = int(re.fullmatch(r"bytes=(\d+)-", rng).group(1)) if rng else 0
            body = data[start:]
            self.send_response(206 if rng else 200)
            if rng:
                self.send_header("Content-Range", f"bytes {start}-{len(data) - 1}/{len(data)}")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            if name in served.interrupt_once:  # half the bytes, then the connection closes
                served.interrupt_once.discard(name)
                self.wfile.write(body[: len(body) // 2])
                self.wfile.flush()
                return
            self.wfile.write(body)

    return Handler


@pytest.fixture
def server():
    served = Served({})
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), _handler(served))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    served.url = f"http://127.0.0.1:{httpd.server_address[1]}/"
    yield served
    httpd.shutdown()
    httpd.server_close()


def _mat_bytes(run, duration_s: float = 30.0) -> tuple[bytes, dict]:
    mat, truth = synthetic.simulate_run(run, {**CFG, "duration_s": duration_s}, SEED)
    buf = io.BytesIO()
    scipy.io.savemat(buf, mat, do_compression=True, oned_as="column")
    return buf.getvalue(), truth


class FakeFigshare:
    """Stands in for pooch's figshare repository of the DOI: the file list with md5 checksums,
    and download URLs on the local server."""

    def __init__(self, served: Served):
        self.served = served

    def populate_registry(self, pup):
        for name, data in self.served.files.items():
            if name.endswith(".mat"):
                pup.registry[name] = "md5:" + hashlib.md5(data).hexdigest()

    def download_url(self, name):
        return self.served.url + name


def _mock_doi(monkeypatch, served: Served) -> list[str]:
    asked: list[str] = []

    def resolve(doi, **kwargs):
        asked.append(doi)
        return FakeFigshare(served)

    monkeypatch.setattr(pooch.core, "doi_to_repository", resolve)
    monkeypatch.setattr(pooch.downloaders, "doi_to_repository", resolve)
    return asked


@pytest.fixture
def figshare_runs(server):
    """Three rider-3 stand-in runs (HR 25, CR 25, HR 30 km/h) and a rider-2 decoy."""
    picks = [r for r in synthetic.stand_in_runs(CFG)
             if (r.system, r.speed_kmh) in {("HR", 25.0), ("CR", 25.0), ("HR", 30.0)}]
    truths = {}
    for r in picks:
        data, truth = _mat_bytes(r)
        server.files[f"{r.run_id:04d}.mat"] = data
        truths[r.run_id] = (r, truth)
    server.files["2045.mat"] = server.files[f"{picks[0].run_id:04d}.mat"]  # rider 2: not needed
    return truths


def test_empty_registry_online_fetches_rider_3_and_extracts(monkeypatch, tmp_path, server,
                                                            figshare_runs):
    asked = _mock_doi(monkeypatch, server)
    monkeypatch.setenv(fetch.ENV, str(tmp_path / "cache"))
    registry = tmp_path / "registry.txt"
    registry.write_text(fetch.REGISTRY.read_text())  # the shipped registry: no file entries
    assert not any(fetch.RUN_FILE.match(ln.split()[0]) for ln in registry.read_text()
                   .splitlines() if ln and not ln.startswith("#"))
    pup = fetch.make_pooch(registry=registry)
    assert fetch.resolve_source("auto", pup) == (
        "figshare", f"downloadable from figshare (DOI {fetch.DOI})")
    assert [a.rstrip("/") for a in asked] == [fetch.DOI]  # pooch keeps the base URL slash
    hr25 = next(rid for rid, (r, _) in figshare_runs.items()
                if (r.system, r.speed_kmh) == ("HR", 25.0))
    server.corrupt_once.add(f"{hr25:04d}.mat")
    events: list[str] = []
    files = fetch.run_files(pup, progressbar=False, events=events)
    assert sorted(files) == sorted(figshare_runs)  # rider 3 only
    assert not any(name == "2045.mat" for name, _ in server.requests)
    # the corrupt copy: reported, removed, fetched again once, then correct
    assert [e for e in events if "does not match its hash" in e][0].startswith(f"{hr25:04d}.mat")
    assert sum(n == f"{hr25:04d}.mat" for n, _ in server.requests) == 2
    for rid, path in files.items():
        assert hashlib.md5(path.read_bytes()).hexdigest() == hashlib.md5(
            server.files[f"{rid:04d}.mat"]).hexdigest()
    # extract: the cadence and the cadence amplitudes of the ground truth
    for rid, path in files.items():
        r, truth = figshare_runs[rid]
        a = runs.analyse_run(path)
        assert a.cadence.cadence_rpm == pytest.approx(r.cadence_rpm, rel=0.005)
        from pedalrepro import spectral

        x = truth["roll_rad"]
        want = spectral.amplitude_at(x - x.mean(), 100.0, r.cadence_rpm / 60)
        assert a.amplitudes["roll_amp_rad"] == pytest.approx(want, abs=5e-5)
    # offline afterwards: everything cached and verified, nothing requested
    n = len(server.requests)
    assert fetch.resolve_source("figshare", pup)[0] == "figshare"
    assert fetch.run_files(pup, progressbar=False) == files and len(server.requests) == n


def test_interrupted_download_resumes(monkeypatch, tmp_path, server, figshare_runs):
    _mock_doi(monkeypatch, server)
    monkeypatch.setenv(fetch.ENV, str(tmp_path / "cache"))
    pup = fetch.make_pooch(registry=None)
    fetch.figshare_registry(pup)
    name = sorted(n for n in server.files if n.startswith("3"))[0]
    size = len(server.files[name])
    server.interrupt_once.add(name)
    events: list[str] = []
    path = fetch.fetch(name, pup, progressbar=False, events=events)
    assert path.read_bytes() == server.files[name]
    got = [r for n, r in server.requests if n == name]
    # first request: the whole file, cut after half; second: the rest, from the bytes kept
    # (the whole 64 KiB chunks written before the cut: between half minus a chunk and half)
    assert len(got) == 2 and got[0] is None
    kept = int(re.fullmatch(r"bytes=(\d+)-", got[1]).group(1))
    assert size // 2 - (1 << 16) < kept <= size // 2
    assert any(f"resuming from {kept} bytes" in e for e in events)
    assert not (path.parent / f"{name}.part").exists()


def test_corrupt_twice_is_an_error_naming_the_file(monkeypatch, tmp_path, server,
                                                   figshare_runs):
    _mock_doi(monkeypatch, server)
    monkeypatch.setenv(fetch.ENV, str(tmp_path / "cache"))
    pup = fetch.make_pooch(registry=None)
    fetch.figshare_registry(pup)
    name = sorted(n for n in server.files if n.startswith("3"))[0]
    good = server.files[name]
    server.files[name] = good[:-1] + bytes([good[-1] ^ 0xFF])  # always corrupt
    with pytest.raises(fetch.HashMismatchError, match=f"{name}: hash mismatch again"):
        fetch.fetch(name, pup, progressbar=False)
    assert sum(n == name for n, _ in server.requests) == 2
    assert not (tmp_path / "cache" / name).exists()


def test_public_subset_over_http_end_to_end(monkeypatch, tmp_path, server):
    real = copy_real_subset(tmp_path / "source")
    for p in real.iterdir():
        server.files[p.name] = p.read_bytes()
    monkeypatch.setenv(fetch.ENV, str(tmp_path / "cache"))
    pup = fetch.make_public_pooch(base_url=server.url)
    server.corrupt_once.add("3045_Y.xlsx")
    server.interrupt_once.add("3045_Z.xlsx")
    events: list[str] = []
    got = fetch.public_files(pup, progressbar=False, events=events)
    assert sorted(got) == sorted(p.name for p in real.iterdir())
    for name, path in got.items():
        assert path.read_bytes() == (real / name).read_bytes()  # sha256-checked bytes
    assert any(e.startswith("3045_Y.xlsx: downloaded file does not match") for e in events)
    assert any(e.startswith("3045_Z.xlsx: download interrupted") for e in events)
    # a cached file altered on disk: reported, removed, fetched again
    cached = tmp_path / "cache" / "3101Y.csv"
    cached.write_bytes(cached.read_bytes()[:-5])
    events.clear()
    assert fetch.fetch("3101Y.csv", pup, progressbar=False, events=events).read_bytes() == \
        (real / "3101Y.csv").read_bytes()
    assert "does not match the registry" in events[0] and "removed" in events[0]
    # extract from the downloaded files: the same numbers as from the local copy
    a = runs.analyse_run(got["3045_X.xlsx"])
    b = runs.analyse_run(real / "3045_X.xlsx")
    assert a.cadence.cadence_rpm == b.cadence.cadence_rpm
    assert a.amplitudes == b.amplitudes


def test_auto_falls_back_when_a_figshare_file_cannot_be_had(monkeypatch, tmp_path, server,
                                                            figshare_runs):
    # the DOI answers but one run file is gone (404): auto falls back to the stand-in plus the
    # real subset (served by the same server), labelled, and says why; figshare fails with one
    # clear message
    _mock_doi(monkeypatch, server)
    real = copy_real_subset(tmp_path / "source")
    for p in real.iterdir():
        server.files[p.name] = p.read_bytes()
    monkeypatch.setenv(fetch.ENV, str(tmp_path / "cache"))
    orig = fetch.make_public_pooch
    monkeypatch.setattr(fetch, "make_public_pooch", lambda *a, **k: orig(base_url=server.url))
    server.missing.add(sorted(figshare_runs)[-1].__format__("04d") + ".mat")
    cfg = {**CFG, "duration_s": 20.0}
    rec = prepare.prepare_runs("auto", tmp_path / "runs", cfg, SEED)
    assert rec["data_source"] == "synthetic"
    assert rec["reason"].startswith("the figshare files could not all be had")
    assert list(rec["public_subset"]) == ["3045"]
    assert (tmp_path / "runs" / "public" / "3045.mat").is_file()
    assert len(list((tmp_path / "runs").glob("3*.mat"))) >= 9  # the stand-in's runs
    with pytest.raises(fetch.DataUnavailableError, match=r"^data_source: figshare, but"):
        prepare.prepare_runs("figshare", tmp_path / "runs2", cfg, SEED)


def test_offline_figshare_is_one_clear_message(monkeypatch, tmp_path):
    def offline(doi, **kwargs):
        raise requests.exceptions.ConnectionError("no route to host (test)")

    monkeypatch.setattr(pooch.core, "doi_to_repository", offline)
    monkeypatch.setenv(fetch.ENV, str(tmp_path))
    with pytest.raises(fetch.DataUnavailableError) as info:
        fetch.resolve_source("figshare", fetch.make_pooch())
    msg = str(info.value)
    assert msg.startswith("data_source: figshare, but the treadmill data")
    assert fetch.ENV in msg and "data_source: auto" in msg and msg.count("\n") == 0
    assert fetch.resolve_source("auto", fetch.make_pooch())[0] == "synthetic"
