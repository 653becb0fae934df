"""The BicycleParameters snapshot (pedalrepro.nonlinear.bicycle_data) and the jobs' imports.

A model-building job reads BicycleParameters' numbers from the snapshot instead of importing
BicycleParameters (1.6 s), computes Moore's parameters itself instead of importing dtk's bicycle
module (0.8 s) and never imports sympy (0.6 s): these tests hold the numbers to the bit and the
imports to the list.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pedalrepro import paths
from pedalrepro.nonlinear import bicycle_data, nonlinear_model

ROOT = Path(__file__).resolve().parents[2]

_DUMP = """
import json, sys
from pedalrepro.nonlinear import bicycle_data
out = {}
for name in ("Browser", "Stratos"):
    for rider in (True, False):
        d = bicycle_data.load(name, rider)
        out[f"{name}_{rider}"] = {"frame": d.frame, "with_rider": d.with_rider, "arms": d.arms}
out["imported"] = sorted(m for m in ("bicycleparameters", "dtk", "matplotlib", "sympy")
                         if m in sys.modules)
print(json.dumps(out))
"""


def _dump(cache: Path) -> dict:
    env = dict(os.environ, PEDALREPRO_CACHE=str(cache))
    done = subprocess.run([sys.executable, "-c", _DUMP], env=env, capture_output=True,
                          text=True, check=True, cwd=ROOT)
    return json.loads(done.stdout)


@pytest.fixture(scope="module")
def dumps(tmp_path_factory):
    """A load that computes (empty cache), one that reads the snapshot it wrote, and one after
    the snapshot files were truncated (hostile: a half-written or corrupt cache file)."""
    cache = tmp_path_factory.mktemp("cache")
    first = _dump(cache)
    files = sorted((cache / "bicycle_data").glob("*.json"))
    second = _dump(cache)
    for f in files:
        f.write_text(f.read_text()[:50])
    third = _dump(cache)
    return first, second, third, files


def test_snapshot_is_written_once_per_bicycle_and_rider(dumps):
    files = dumps[3]
    assert sorted(f.name.split("_")[0] + "_" + f.name.split("_")[1] for f in files) == [
        "Browser_alone", "Browser_rider", "Stratos_alone", "Stratos_rider"]


def test_snapshot_load_equals_computed_load_to_the_bit(dumps):
    """JSON keeps every float: the second process reads exactly what the first computed, and
    only the first imported BicycleParameters."""
    first, second, _, _ = dumps
    assert {k: v for k, v in second.items() if k != "imported"} == {
        k: v for k, v in first.items() if k != "imported"}
    assert "bicycleparameters" in first["imported"]
    assert second["imported"] == []


def test_truncated_snapshot_is_recomputed_not_trusted(dumps):
    first, _, third, files = dumps
    assert {k: v for k, v in third.items() if k != "imported"} == {
        k: v for k, v in first.items() if k != "imported"}
    assert "bicycleparameters" in third["imported"]
    for f in files:  # rewritten whole
        assert set(json.loads(f.read_text())) == {"frame", "with_rider", "arms"}


def test_snapshot_equals_bicycleparameters_and_yeadon(dumps):
    """Against BicycleParameters itself (the lazily built bicycle of this process): the
    benchmark parameters with the rider to 1e-14 relative (BicycleParameters' own sums vary in
    the last bit with the memory layout of a process), and mass conservation of the arm parts:
    the five solids of the right forearm and hand make up Yeadon's segment B2, the segments'
    masses are Yeadon's."""
    snap = dumps[0]["Browser_True"]
    bike = bicycle_data.load("Browser", rider=True).bicycle
    theirs = {k: float(getattr(v, "nominal_value", v))
              for k, v in bike.parameters["Benchmark"].items()}
    for k, v in snap["with_rider"].items():
        assert v == pytest.approx(theirs[k], rel=1e-14, abs=1e-15), k
    parts = snap["arms"]["parts"]
    human = bike.human
    for seg in ("A1", "A2", "B1", "B2"):
        assert parts[seg]["mass"] == pytest.approx(float(getattr(human, seg).mass), rel=1e-14)
    solids = sum(parts[s]["mass"] for s in ("b2", "b3", "b4", "b5", "b6"))
    assert solids == pytest.approx(parts["B2"]["mass"], rel=1e-12)
    # the right arm is on the right (bicycle y > 0): shoulder, elbow and grip
    for point in ("shoulder", "elbow", "grip"):
        assert snap["arms"]["points"][point][1] > 0


def test_snapshot_key_follows_the_parameter_files(tmp_path, monkeypatch):
    """Any byte of data/parameters/bicycleparameters changes the key (a stale snapshot is never
    read); the same files give the same key."""
    copy = tmp_path / "parameters"
    shutil.copytree(paths.PARAMETERS / "bicycleparameters", copy / "bicycleparameters")
    monkeypatch.setattr(paths, "PARAMETERS", copy)
    before = bicycle_data.snapshot_key("Browser", True)
    assert bicycle_data.snapshot_key("Browser", True) == before
    target = next(p for p in sorted((copy / "bicycleparameters").rglob("*.txt")))
    target.write_bytes(target.read_bytes() + b" ")
    assert bicycle_data.snapshot_key("Browser", True) != before
    assert bicycle_data.snapshot_key("Browser", False) != bicycle_data.snapshot_key(
        "Browser", True)


@pytest.mark.parametrize("name, rider", [("Browser", True), ("Stratos", True),
                                         ("Browser", False), ("Stratos", False)])
def test_moore_parameters_equal_dtk_to_the_bit(name, rider):
    """Moore's (2012) conversion as written in nonlinear_model equals dtk's
    ``benchmark_to_moore`` (the one SymBRiM uses) exactly, on the thesis's bicycles and on the
    Meijaard benchmark bicycle."""
    from dtk.bicycle import benchmark_parameters, benchmark_to_moore

    for bench in (dict(bicycle_data.load(name, rider).with_rider, g=9.81),
                  dict(benchmark_parameters())):
        bench = {k: float(v) for k, v in bench.items()}
        ours = nonlinear_model.moore_parameters(bench)
        mp = benchmark_to_moore(dict(bench))
        pairs = {"front_frame_body_mass": "me", "front_frame_d2": "d2", "front_frame_d3": "d3",
                 "front_frame_ixx": "ie11", "front_frame_iyy": "ie22", "front_frame_izz": "ie33",
                 "front_frame_izx": "ie31", "front_frame_l3": "l3", "front_frame_l4": "l4",
                 "rear_frame_body_mass": "mc", "rear_frame_d1": "d1", "rear_frame_ixx": "ic11",
                 "rear_frame_iyy": "ic22", "rear_frame_izz": "ic33", "rear_frame_izx": "ic31",
                 "rear_frame_l1": "l1", "rear_frame_l2": "l2"}
        for ours_key, dtk_key in pairs.items():
            assert ours[ours_key] == mp[dtk_key], ours_key
        assert np.isfinite(list(ours.values())).all()


def test_model_jobs_import_no_sympy_matplotlib_dtk():
    """The modules a map, branch, sweep or linearisation job imports leave out sympy,
    matplotlib, dtk and BicycleParameters (2.5-3 s of every such job)."""
    code = ("import sys\n"
            "from pedalrepro.nonlinear import calibration, sweep, nonlinear_model, codegen\n"
            "from pedalrepro import periodic\n"
            "print(sorted(m for m in ('sympy', 'matplotlib', 'dtk', 'bicycleparameters', "
            "'symbrim') if m in sys.modules))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert done.stdout.strip() == "[]"
