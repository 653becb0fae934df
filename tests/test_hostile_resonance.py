"""Hostile bicycles and riders for ``pedalrepro resonance`` (issue 22, case 3).

Every impossible or unreadable input is refused before any computation, naming the file and the
parameter (or the option); a valid one gives the same bicycle as before. Each case loads a copy
of the shipped Rigid bicycle and rider Jason (BicycleParameters' format) with one line changed;
no map is computed (``load_bicycle`` and the CLI stop first).
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from pedalrepro import cli, own_bicycle, paths

DATA = paths.PARAMETERS / "bicycleparameters"
SEAT_M = 0.72  # the book's example (rules/own_bicycle.smk)


@pytest.fixture()
def folder(tmp_path) -> Path:
    """A copy of the Rigid bicycle and rider Jason."""
    for sub in ("bicycles/Rigid", "riders/Jason"):
        shutil.copytree(DATA / sub, tmp_path / sub)
    return tmp_path


def measured(folder: Path) -> Path:
    return folder / "bicycles" / "Rigid" / "RawData" / "RigidMeasured.txt"


def benchmark(folder: Path) -> Path:
    return folder / "bicycles" / "Rigid" / "Parameters" / "RigidBenchmark.txt"


def yeadon(folder: Path) -> Path:
    return folder / "riders" / "Jason" / "RawData" / "JasonYeadonMeas.txt"


def edit(path: Path, name: str, new_line: str | None, sep: str = "=") -> int:
    """Replace the line defining ``name`` (None: delete it); returns its line number."""
    lines = path.read_text().splitlines()
    i = next(k for k, ln in enumerate(lines) if re.match(rf"{name}\s*{sep}", ln))
    if new_line is None:
        del lines[i]
    else:
        lines[i] = new_line
    path.write_text("\n".join(lines) + "\n")
    return i + 1


def refused(folder, *fragments, **kw):
    with pytest.raises(ValueError) as info:
        own_bicycle.load_bicycle(folder, "Rigid", "Jason", **({"seat_height_m": SEAT_M} | kw))
    msg = str(info.value)
    for f in fragments:
        assert f in msg, msg
    return msg


# --- the bicycle's parameter file -------------------------------------------------------------

@pytest.mark.parametrize("which", [benchmark, measured])
@pytest.mark.parametrize("value", ["-22.90+/-0.01", "0.0"])
def test_non_positive_mass_is_refused(folder, value, which):
    """A negative mB gave rc 0 and a full map."""
    edit(which(folder), "mB", f"mB = {value}")
    refused(folder, str(which(folder)), "'mB'", "must be positive")


@pytest.mark.parametrize("value", ["nan", "inf", "-inf"])
def test_non_finite_parameter_is_refused_with_file_and_line(folder, value):
    """A NaN seat-tube angle gave 10201 of 10302 NaN cells and "peak 0" (rc 0)."""
    line = edit(measured(folder), "lamst", f"lamst = {value}")
    refused(folder, f"{measured(folder)}, line {line}", "'lamst'", "not a finite number")


def test_missing_parameter_names_file_and_parameter(folder):
    """A missing mB said only 'mB'."""
    edit(benchmark(folder), "mB", None)
    refused(folder, str(benchmark(folder)), "'mB' missing")


def test_missing_measured_parameter_names_the_file(folder):
    """Without Parameters/RigidBenchmark.txt BicycleParameters computes from the measured file."""
    benchmark(folder).unlink()
    edit(measured(folder), "mB", None)
    refused(folder, str(measured(folder)), "'mB' missing")


@pytest.mark.parametrize("bad_line, why", [
    ("mB 22.90+/-0.01", "is not 'name = value'"),   # an IndexError traceback before
    ("", "is not 'name = value'"),
    ("= 22.9", "is not 'name = value'"),
    ("mB = 22.9 kg", "is not a number"),
    ("mB = 22.9+/-", "is not a number"),
])
def test_malformed_line_is_refused_with_file_and_line(folder, bad_line, why):
    line = edit(measured(folder), "mB", bad_line)
    refused(folder, f"{measured(folder)}, line {line}", why)


def test_parameter_given_twice_is_refused(folder):
    path = measured(folder)
    path.write_text(path.read_text() + "mB = 50.0\n")
    refused(folder, str(path), "'mB' is given twice")


def test_lamst_out_of_range_is_refused_with_its_source(folder):
    edit(measured(folder), "lamst", f"lamst = {math.radians(200)}")
    refused(folder, "seat-tube angle 200 deg outside 45-90 deg", f"{measured(folder)}: lamst")


# --- the rider's Yeadon files ------------------------------------------------------------------

def test_negative_rider_measurement_is_refused(folder):
    edit(yeadon(folder), "Ls1L", "Ls1L: -17.6", sep=":")
    refused(folder, str(yeadon(folder)), "'Ls1L'", "must be positive")


def test_nan_rider_mass_is_refused(folder):
    edit(yeadon(folder), "totalmass", "totalmass: .nan", sep=":")
    refused(folder, str(yeadon(folder)), "'totalmass'", "not a finite number")


def test_malformed_yeadon_file_names_the_line(folder):
    line = edit(yeadon(folder), "Ls1L", "Ls1L: [17.6", sep=":")
    refused(folder, f"{yeadon(folder)}, line", "not a Yeadon file")
    assert line > 1


def test_missing_rider_measurement_is_refused_naming_the_files(folder):
    edit(yeadon(folder), "Ls1L", None, sep=":")
    refused(folder, str(yeadon(folder)), "BicycleParameters cannot build")


# --- seat, crank and the legs (options) --------------------------------------------------------

@pytest.mark.parametrize("kw, fragment", [
    ({"seat_tube_angle_deg": 200.0}, "seat-tube angle 200 deg outside 45-90 deg"),
    ({"seat_tube_angle_deg": float("nan")}, "seat-tube angle not a finite number"),
    ({"seat_tube_angle_deg": 30.0}, "--seat-tube-angle-deg 30.0"),
    ({"seat_height_m": 0.0}, "seat height 0 m must be positive"),
    ({"seat_height_m": -0.72}, "seat height -0.72 m must be positive"),
    ({"seat_height_m": float("inf")}, "seat height not a finite number"),
    ({"crank_length_m": 0.0}, "crank length 0 m outside 0.08-0.25 m"),
    ({"crank_length_m": -0.17}, "crank length -0.17 m outside"),
    ({"crank_length_m": float("nan")}, "crank length not a finite number"),
    ({"seat_height_m": 0.10, "crank_length_m": 0.17}, "above the crank length"),
])
def test_impossible_seat_or_crank_is_refused(folder, kw, fragment):
    """A zero or negative seat height or crank gave rc 0 and a full map."""
    refused(folder, fragment, **kw)


def test_rigid_default_seat_is_refused_with_the_fix():
    """README's example on the shipped Rigid bicycle: its lst + lsp = 0.751 m leaves the legs
    0.9 mm short; the refusal says which option fixes it, and the range it must lie in, which
    equals l_ul + l_ll - l_cr (legs.yaml) to the millimetre."""
    with pytest.raises(ValueError) as info:
        own_bicycle.load_bicycle(DATA, "Rigid", "Jason")
    msg = str(info.value)
    assert "0.9 mm short" in msg and "--seat-height-m between" in msg
    assert "RigidMeasured.txt: lst + lsp" in msg
    hi = float(re.search(r"between [\d.]+ and ([\d.]+) m", msg).group(1))
    from pedalrepro import legs
    g = legs.leg_geometry("hybrid", "O")
    assert hi == pytest.approx(g.thigh_length_m + g.shank_length_m - g.crank_length_m, abs=1e-3)
    # the suggested height works
    own_bicycle.load_bicycle(DATA, "Rigid", "Jason", seat_height_m=hi)


def test_valid_copy_equals_the_shipped_bicycle(folder):
    """The checks change nothing for a valid folder: the copy gives the shipped bicycle's model."""
    a = own_bicycle.load_bicycle(folder, "Rigid", "Jason", seat_height_m=SEAT_M)
    b = own_bicycle.load_bicycle(DATA, "Rigid", "Jason", seat_height_m=SEAT_M)
    for x, y in zip((a.model.M, a.model.K0), (b.model.M, b.model.K0), strict=True):
        np.testing.assert_array_equal(x, y)
    assert a.geometry.seat_tube_plus_post_m == SEAT_M
    assert a.geometry.seat_tube_angle_rad == pytest.approx(1.267109037, abs=1e-12)


# --- the benchmark parameters of bicycle + rider ------------------------------------------------

@pytest.fixture()
def meijaard() -> dict[str, float]:
    """Meijaard et al. (2007) benchmark bicycle (BicycleParameters' Benchmark folder)."""
    return own_bicycle.read_parameter_file(
        DATA / "bicycles" / "Benchmark" / "Parameters" / "BenchmarkBenchmark.txt")


def test_meijaard_benchmark_passes(meijaard):
    own_bicycle.check_benchmark(meijaard, "benchmark")


@pytest.mark.parametrize("change, fragment", [
    ({"IBxz": 6.0}, "rear frame + rider (IBxx, IByy, IBzz, IBxz) is not positive definite"),
    ({"IHxx": -0.05}, "front assembly (IHxx, IHyy, IHzz, IHxz) is not positive definite"),
    ({"IByy": 30.0}, "breaks the triangle inequality"),
    ({"IRyy": 0.5}, "exceeds mR rR^2"),
    ({"IFxx": 0.0}, "front wheel's inertia must be positive"),
    ({"zB": 0.9}, "zB = 0.9 m: the centre of mass must be above the ground"),
    ({"rF": -0.35}, "rF = -0.35 must be positive"),
    ({"mH": 0.0}, "mH = 0 must be positive"),
    ({"g": 0.0}, "g = 0 m/s^2 outside"),
    ({"lam": 2.0}, "lam = 2 rad (steer-axis tilt)"),
    ({"c": 1.5}, "c = 1.5 m (trail) is not below the wheelbase"),
    ({"w": float("nan")}, "not finite: w = nan"),
])
def test_impossible_benchmark_parameters_are_refused(meijaard, change, fragment):
    with pytest.raises(ValueError) as info:
        own_bicycle.check_benchmark(meijaard | change, "my.txt")
    assert str(info.value).startswith("my.txt: ") and fragment in str(info.value), info.value


def test_missing_benchmark_parameter_is_named(meijaard):
    del meijaard["IHxz"]
    with pytest.raises(ValueError, match=r"my.txt: parameter\(s\) IHxz missing"):
        own_bicycle.check_benchmark(meijaard, "my.txt")


# --- the command line: exit 2, one line naming the file, no traceback -------------------------

def test_cli_refuses_without_traceback(folder, capsys):
    line = edit(measured(folder), "mB", "mB 22.90")
    rc = cli.main(["resonance", str(folder), "--bicycle", "Rigid", "--rider", "Jason",
                   "--seat-height-m", "0.72", "--out", str(folder / "out")])
    err = capsys.readouterr().err
    assert rc == 2
    assert f"{measured(folder)}, line {line}" in err and "Traceback" not in err
    assert not (folder / "out").exists()


def test_cli_nan_option_is_refused(folder, capsys):
    rc = cli.main(["resonance", str(folder), "--bicycle", "Rigid", "--rider", "Jason",
                   "--seat-tube-angle-deg", "nan", "--seat-height-m", "0.72", "--out",
                   str(folder / "out")])
    assert rc == 2
    assert "seat-tube angle not a finite number" in capsys.readouterr().err


# --- cases that already held -------------------------------------------------------------------

def test_missing_folder_bicycle_or_rider_is_named(tmp_path, folder):
    with pytest.raises(FileNotFoundError, match=str(tmp_path / "nowhere")):
        own_bicycle.load_bicycle(tmp_path / "nowhere", "Rigid", "Jason")
    with pytest.raises(FileNotFoundError, match="bicycles found: \\['Rigid'\\]"):
        own_bicycle.load_bicycle(folder, "Mybike", "Jason")
    with pytest.raises(FileNotFoundError, match="JasonRigidYeadonCFG.txt|cannot place the rider"):
        (folder / "riders" / "Jason" / "RawData" / "JasonRigidYeadonCFG.txt").unlink()
        own_bicycle.load_bicycle(folder, "Rigid", "Jason", seat_height_m=SEAT_M)
