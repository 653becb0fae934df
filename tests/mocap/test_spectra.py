"""The measured closed-loop spectra source (pedalrepro.mocap.spectra): Moore's MotionCapture
figure files, read from copies of ../shared/reference/moore-spectra (sha256-checked) and
downloaded through pooch from a local HTTP server."""

from __future__ import annotations

import hashlib
import os
import shutil
import threading
from functools import partial
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest
from required import REAL, skip_unless_required

from pedalrepro import paths
from pedalrepro.mocap import fetch, spectra

SHARED = Path(os.environ.get("PEDALREPRO_SPECTRA_DIR") or
              paths.ROOT.parent / "shared" / "reference" / "moore-spectra")
SPEEDS = [2.0, 3.0, 4.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0]
#: Cadence lines of the README (Hz), 2-30 km/h.
CADENCE_HZ = [0.14, 0.23, 0.32, 0.40, 0.80, 0.86, 1.16, 1.068, 1.28]


def _shared() -> Path:
    if not SHARED.is_dir():
        skip_unless_required(REAL, f"spectra copies not found at {SHARED}; CI provides them")
    return SHARED


@pytest.fixture
def data_dir(tmp_path, monkeypatch) -> Path:
    d = tmp_path / "data"
    d.mkdir()
    monkeypatch.setenv(fetch.ENV, str(d))
    return d


def _sha_sums(folder: Path) -> dict[str, str]:
    out = {}
    for line in (folder / "SHA256SUMS").read_text().splitlines():
        h, name = line.split()
        out[name] = h
    return out


def test_shared_copies_match_the_registry_sha256():
    src = _shared()
    sums = _sha_sums(src)
    pup = spectra.make_pooch()
    assert set(pup.registry) == set(sums)
    for name, h in sums.items():
        assert pup.registry[name] == f"sha256:{h}"
        assert hashlib.sha256((src / name).read_bytes()).hexdigest() == h
        assert "e46740bf3d0b41c355e3bce5154c99ecbf3fcd8a/MatlabCode/" + name in pup.urls[name]


def test_reader_offline_from_the_data_folder(data_dir):
    for p in _shared().glob("*.fig"):
        shutil.copy2(p, data_dir / p.name)
    pup = spectra.make_pooch(base_url="http://127.0.0.1:9/")  # unreachable: must not be asked
    files = spectra.fetch_files(pup)
    s = spectra.read_all(files)
    assert sorted(s["roll"]) == SPEEDS == sorted(s["steer"]) == sorted(s["yaw"])
    assert sorted(s["steer_second"]) == [5.0, 10.0, 15.0, 20.0, 25.0, 30.0]
    t = spectra.cadence_table(s)
    np.testing.assert_allclose(t.cadence_hz, CADENCE_HZ, atol=1e-12)
    assert (t.source == spectra.LABEL).all()
    # freqampl's axis for n = 6000 samples at 100 Hz: step Fs/(n-2), 180 points below 3 Hz
    for v in SPEEDS[1:]:
        sp = s["steer"][v]
        np.testing.assert_allclose(np.diff(sp.frequency_hz), 100.0 / 5998, rtol=1e-6)
        assert len(sp.frequency_hz) == 180
        assert abs(sp.amplitude_rad[0]) < 1e-15  # the mean was removed
    # the 2 km/h axis has its own resolution and is cut at 3 Hz here
    assert np.diff(s["roll"][2.0].frequency_hz) == pytest.approx(0.0344116, rel=1e-5)
    assert s["roll"][2.0].frequency_hz.max() < 3.0
    # README: steer about 0.17 at 2 km/h and 0.011-0.014 at 25-30 km/h (nearest bin)
    row = t.set_index("speed_kmh")
    assert row.loc[2.0, "steer_nearest_rad"] == pytest.approx(0.17, abs=0.01)
    assert 0.010 < row.loc[30.0, "steer_nearest_rad"] < row.loc[25.0, "steer_nearest_rad"] < 0.015
    assert (row.steer_peak2_rad >= row.steer_nearest_rad).all()


def test_cadence_amplitude_reads_nearest_bin_and_peak():
    f = np.arange(10) * 0.1
    a = np.array([0, 1, 2, 3, 9, 4, 1, 0, 0, 0], float)
    sp = spectra.SpeedSpectrum(20.0, f, a, cadence_hz=0.21, weave_hz=0.5)
    assert sp.at_cadence() == (2.0, 9.0)


@pytest.fixture
def server(tmp_path):
    served = tmp_path / "served"
    served.mkdir()
    for p in _shared().glob("*.fig"):
        shutil.copy2(p, served / p.name)
    handler = partial(SimpleHTTPRequestHandler, directory=str(served))
    handler.log_message = lambda *a: None
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield served, f"http://127.0.0.1:{httpd.server_address[1]}/"
    httpd.shutdown()
    httpd.server_close()


def test_download_through_a_local_server_and_hash_check(server, data_dir):
    served, url = server
    files = spectra.fetch_files(spectra.make_pooch(base_url=url))
    sums = _sha_sums(_shared())
    for name, p in files.items():
        assert p.parent == data_dir
        assert hashlib.sha256(p.read_bytes()).hexdigest() == sums[name]
    assert spectra.cadence_table(spectra.read_all(files)).shape[0] == 9
    # a server copy that is not the published file is refused, naming it
    for p in data_dir.glob("*.fig"):
        p.unlink()
    name = "pedalingYAWfrequencyallspeeds.fig"
    (served / name).write_bytes(b"not the figure")
    with pytest.raises(fetch.HashMismatchError, match=name):
        spectra.fetch_files(spectra.make_pooch(base_url=url))


def test_a_file_that_is_not_a_figure_is_an_error_naming_it(tmp_path):
    bad = tmp_path / "bad.fig"
    bad.write_bytes(b"\x00" * 200)
    with pytest.raises(spectra.SpectraFormatError, match="bad.fig"):
        spectra.read_figure(bad)
