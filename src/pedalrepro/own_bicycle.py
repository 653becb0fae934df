"""Your own bicycle: the pedalling resonance of any bicycle and rider in BicycleParameters' format.

From a data folder laid out as BicycleParameters expects (J. K. Moore;
``bicycles/<Name>/Parameters/<Name>Benchmark.txt`` and/or ``bicycles/<Name>/RawData/
<Name>Measured.txt``, ``riders/<Rider>/RawData/<Rider>YeadonMeas.txt`` and
``<Rider><Name>YeadonCFG.txt``, or a precomputed ``riders/<Rider>/Parameters/
<Rider><Name>Benchmark.txt``) this module builds

* the linear Whipple model with a rigid rider (Sec 3.1.1; BicycleParameters adds the Yeadon rider
  to the rear frame, dynamicisttoolkit gives ``M``, ``C1``, ``K0``, ``K2`` of Eq 3.1),
* the pedalling torques (Sec 2.1, Eq 2.15, Eq 3.14): the dual four-bar legs of
  ``data/parameters/legs.yaml`` (segment lengths and masses, hip width) on this bicycle's seat
  (seat tube + seat post ``lst + lsp`` and seat-tube angle ``lamst`` of its measured data, or
  explicit values) with its crank length, and its own ``c cos(lam) / w``,

and computes the eigenvalues versus speed (weave and capsize speeds, self-stable range; Sec
3.2.1), the particular-solution (PS) amplitude map over speed and cadence (Sec 3.1.2.2.1,
batched), its resonance ridge (the cadence of peak amplitude at each speed) and where that ridge
falls inside normal cycling (Sec 3.1.3.2, Fig 3.8, 3.35: the ellipse of config
``linear.normal_cycling_*`` and the gear-ratio lines).

``pedalrepro resonance BICYCLE_DIR --bicycle NAME --rider RIDER`` runs it from the command line.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from . import disturbance, gears, legs, linear, response
from .params import LinearModel

__all__ = [
    "DATA_FILES", "BENCHMARK_KEYS", "SEAT_TUBE_ANGLE_DEG", "CRANK_LENGTH_M", "GRAVITY_M_S2",
    "BicycleDataError", "read_parameter_file", "read_yeadon_file", "check_bicycle_file",
    "check_benchmark", "check_seat", "reach_fix", "OwnBicycle", "check_folder", "seat_geometry",
    "load_bicycle", "torques", "ResonanceMap", "resonance_map", "summary", "write_map_csv",
    "write_summary_csv", "plot", "run", "add_cli",
]

#: The book's example (rule ``own_bicycle_resonance``, a bicycle the thesis did not study): its
#: files are the rule's inputs (pedalrepro.dependencies). Any other folder is the user's.
DATA_FILES: tuple[str, ...] = ("data/parameters/bicycleparameters/bicycles/Rigid",
                               "data/parameters/bicycleparameters/riders/Jason")


#: The benchmark parameters of Meijaard et al. (2007, Table 1) that the linear model needs.
BENCHMARK_KEYS: tuple[str, ...] = (
    "w", "c", "lam", "g", "rR", "mR", "IRxx", "IRyy", "xB", "zB", "mB", "IBxx", "IByy", "IBzz",
    "IBxz", "xH", "zH", "mH", "IHxx", "IHyy", "IHzz", "IHxz", "rF", "mF", "IFxx", "IFyy")
#: Seat-tube angles accepted (deg from the horizontal): a hip behind and above the crank axis.
#: Road, city and hybrid frames have 68-76 deg (the thesis bicycles 68.5-71 deg, legs.yaml;
#: BicycleParameters' Rigid 72.6 deg); 45-90 deg leaves room for any upright or recumbent-like
#: seat that the dual four-bar legs of Sec 2.1.1 can model (beyond 90 deg the hip is ahead of
#: the crank axis).
SEAT_TUBE_ANGLE_DEG: tuple[float, float] = (45.0, 90.0)
#: Crank lengths accepted (m): cranks are made 0.150-0.185 m (the thesis's 0.17 m class,
#: legs.yaml); 0.08-0.25 m covers children's and special cranks.
CRANK_LENGTH_M: tuple[float, float] = (0.08, 0.25)
#: Earth's surface gravity, 9.78 (equator) to 9.83 m/s^2 (poles), with a margin.
GRAVITY_M_S2: tuple[float, float] = (9.7, 9.9)


class BicycleDataError(ValueError):
    """A bicycle or rider file that cannot be read or describes an impossible bicycle or rider
    (the message names the file and the parameter)."""


def read_parameter_file(path: str | Path) -> dict[str, float]:
    """The nominal values of a BicycleParameters parameter file (``name = v+/-u, v+/-u``).

    Checks every line as BicycleParameters' own reader would read it
    (``bicycleparameters.io.load_parameter_text_file``: a line not starting with ``#`` is
    ``name = value[, value...]``, each value a number with an optional ``+/-`` uncertainty,
    several values averaged), so that a malformed line is refused here, with the file and line,
    instead of as an IndexError inside BicycleParameters.

    Raises
    ------
    BicycleDataError
        Naming the file, the line and the parameter: a line without ``=``, an empty name, a
        value that is not a number, a NaN or infinite value, a name given twice.
    """
    from uncertainties import ufloat_fromstr

    path = Path(path)
    out: dict[str, float] = {}
    for i, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        if line.startswith("#"):
            continue
        text = line.strip().split("#")[0]
        name, eq, rhs = text.partition("=")
        name = name.strip()
        if not eq or not name or not rhs.strip():
            raise BicycleDataError(f"{path}, line {i}: {line.strip()!r} is not 'name = value' "
                                   "(BicycleParameters' format; comment lines start with #)")
        values = []
        for item in rhs.split(","):
            try:  # as BicycleParameters parses it: ufloat_fromstr when the line has a +/-
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # "std_dev==0" of a +/-0.0
                    values.append(ufloat_fromstr(item).nominal_value if "+/-" in rhs
                                  else float(item))
            except ValueError:
                raise BicycleDataError(f"{path}, line {i}: parameter {name!r}: {item.strip()!r} "
                                       "is not a number (value or value+/-uncertainty)") from None
        if not all(np.isfinite(values)):
            raise BicycleDataError(f"{path}, line {i}: parameter {name!r} = {rhs.strip()} is "
                                   "not a finite number")
        if name in out:
            raise BicycleDataError(f"{path}, line {i}: parameter {name!r} is given twice")
        out[name] = float(np.mean(values))
    return out


def read_yeadon_file(path: str | Path, *, positive: bool) -> dict[str, float]:
    """The values of a Yeadon measurement or configuration file (YAML ``name: value``).

    ``positive``: every value must be above zero (the measurement file: lengths, perimeters,
    widths, depths, the conversion factor and the total mass); otherwise finite (the
    configuration file's joint angles, rad).

    Raises
    ------
    BicycleDataError
        Naming the file (and the line, for a YAML syntax error) and the parameter.
    """
    import yaml

    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(errors="replace"))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f", line {mark.line + 1}" if mark is not None else ""
        raise BicycleDataError(f"{path}{where}: not a Yeadon file ('name: value' lines): "
                               f"{getattr(exc, 'problem', None) or exc}") from None
    if not isinstance(data, dict):
        raise BicycleDataError(f"{path}: not a Yeadon file (a 'name: value' line per parameter)")
    out = {}
    for name, value in data.items():
        if isinstance(value, bool) or not isinstance(value, int | float) \
                or not np.isfinite(value):
            raise BicycleDataError(f"{path}: parameter {name!r} = {value!r} is not a finite "
                                   "number")
        if positive and not value > 0:
            raise BicycleDataError(f"{path}: parameter {name!r} = {value!r} must be positive "
                                   "(a length, perimeter, width, depth or mass)")
        out[str(name)] = float(value)
    return out


def _positive_names(values: Mapping[str, float]) -> list[str]:
    """Parameters of a bicycle file that are positive by their nature: masses ``m*``, wheel
    radii ``r*``, the measured rolled distances ``dR``/``dF`` and revolutions ``nR``/``nF``,
    pendulum periods ``T*``, seat tube and post ``lst``/``lsp``, gravity ``g``."""
    import re

    pattern = re.compile(r"^(m[A-Z]\w*|r[RF]|d[RF]|n[RF]|T[ct][A-Z]\w*|lst|lsp|g)$")
    return [k for k in values if pattern.match(k)]


def check_bicycle_file(path: str | Path) -> dict[str, float]:
    """:func:`read_parameter_file` plus the signs physics fixes (:func:`_positive_names`)."""
    values = read_parameter_file(path)
    for k in _positive_names(values):
        if not values[k] > 0:
            raise BicycleDataError(f"{path}: parameter {k!r} = {values[k]:g} must be positive "
                                   "(a mass, radius, distance, period or length)")
    return values


def check_benchmark(par: Mapping[str, float], source: str) -> None:
    """Physical check of the benchmark parameters of bicycle + rider (Meijaard et al. 2007,
    Table 1; z points down), before any computation.

    * every parameter of :data:`BENCHMARK_KEYS` present and finite;
    * masses ``mR, mB, mH, mF``, radii ``rR, rF`` and the wheelbase ``w`` positive, gravity in
      :data:`GRAVITY_M_S2`;
    * the steer-axis tilt ``lam`` within (-90, 90) deg, the trail ``|c|`` below the wheelbase;
    * the centres of mass of the rear frame and the front assembly above the ground
      (``zB, zH < 0``);
    * each inertia matrix positive definite with principal moments obeying the triangle
      inequality (``I1 <= I2 + I3``, true of every rigid body), and each wheel's polar moment
      at most that of a ring of its mass and radius (``IRyy <= mR rR^2``).

    Raises
    ------
    BicycleDataError
        Naming ``source`` (the file(s) the parameters came from) and the parameter.
    """
    missing = [k for k in BENCHMARK_KEYS if k not in par]
    if missing:
        raise BicycleDataError(f"{source}: parameter(s) {', '.join(missing)} missing "
                               "(Meijaard et al. 2007 benchmark parameters)")
    bad = [k for k in BENCHMARK_KEYS if not np.isfinite(par[k])]
    if bad:
        raise BicycleDataError(f"{source}: parameter(s) {', '.join(bad)} not finite: "
                               + ", ".join(f"{k} = {par[k]}" for k in bad))
    errors = [f"{k} = {par[k]:g} must be positive" for k in ("mR", "mB", "mH", "mF", "rR",
                                                              "rF", "w") if not par[k] > 0]
    lo, hi = GRAVITY_M_S2
    if not lo <= par["g"] <= hi:
        errors.append(f"g = {par['g']:g} m/s^2 outside {lo}-{hi} (Earth's surface gravity)")
    if not abs(par["lam"]) < np.pi / 2:
        errors.append(f"lam = {par['lam']:g} rad (steer-axis tilt) outside (-pi/2, pi/2)")
    if par["w"] > 0 and not abs(par["c"]) < par["w"]:
        errors.append(f"c = {par['c']:g} m (trail) is not below the wheelbase w = {par['w']:g}")
    for k in ("zB", "zH"):
        if not par[k] < 0:
            errors.append(f"{k} = {par[k]:g} m: the centre of mass must be above the ground "
                          "(z points down, Meijaard 2007)")
    bodies = {"rear frame + rider (IBxx, IByy, IBzz, IBxz)": ("IBxx", "IByy", "IBzz", "IBxz"),
              "front assembly (IHxx, IHyy, IHzz, IHxz)": ("IHxx", "IHyy", "IHzz", "IHxz")}
    for what, (xx, yy, zz, xz) in bodies.items():
        inertia = np.array([[par[xx], 0, par[xz]], [0, par[yy], 0], [par[xz], 0, par[zz]]])
        moments = np.linalg.eigvalsh(inertia)
        if not moments[0] > 0:
            errors.append(f"the inertia matrix of the {what} is not positive definite "
                          f"(principal moments {', '.join(f'{x:.4g}' for x in moments)})")
        elif moments[2] > moments[0] + moments[1] + 1e-12 * moments[2]:
            errors.append(f"the inertia matrix of the {what} breaks the triangle inequality "
                          f"(principal moments {', '.join(f'{x:.4g}' for x in moments)})")
    for wheel, (m, r, ixx, iyy) in {"rear": ("mR", "rR", "IRxx", "IRyy"),
                                    "front": ("mF", "rF", "IFxx", "IFyy")}.items():
        if not (par[ixx] > 0 and par[iyy] > 0):
            errors.append(f"{ixx} = {par[ixx]:g}, {iyy} = {par[iyy]:g}: the {wheel} wheel's "
                          "inertia must be positive")
        elif par[m] > 0 and par[r] > 0 and par[iyy] > par[m] * par[r] ** 2 * (1 + 1e-9):
            errors.append(f"{iyy} = {par[iyy]:g} kg m^2 exceeds {m} {r}^2 = "
                          f"{par[m] * par[r] ** 2:.4g} (a ring, the largest polar moment of a "
                          f"{wheel} wheel of that mass and radius)")
    if errors:
        raise BicycleDataError(f"{source}: impossible bicycle or rider:\n  "
                               + "\n  ".join(errors))


def check_seat(seat_height_m: float, seat_tube_angle_rad: float, crank_length_m: float,
               source: str) -> None:
    """Seat and crank of the leg model (Sec 2.1.1) finite and in range (:data:`CRANK_LENGTH_M`,
    :data:`SEAT_TUBE_ANGLE_DEG`), the hip farther from the crank axis than the crank is long;
    :class:`BicycleDataError` naming ``source`` (an option or a file's parameter)."""
    values = {"seat height": seat_height_m, "seat-tube angle": seat_tube_angle_rad,
              "crank length": crank_length_m}
    bad = [k for k, x in values.items() if not np.isfinite(x)]
    if bad:
        raise BicycleDataError(f"{source}: {', '.join(bad)} not a finite number")
    lo, hi = CRANK_LENGTH_M
    errors = []
    if not lo <= crank_length_m <= hi:
        errors.append(f"crank length {crank_length_m:g} m outside {lo}-{hi} m (cranks are made "
                      "0.150-0.185 m; --crank-length-m)")
    lo, hi = SEAT_TUBE_ANGLE_DEG
    deg = float(np.rad2deg(seat_tube_angle_rad))
    if not lo <= deg <= hi:
        errors.append(f"seat-tube angle {deg:g} deg outside {lo:g}-{hi:g} deg from the horizontal "
                      "(road and city frames 68-76 deg; --seat-tube-angle-deg, or lamst in rad)")
    if not seat_height_m > max(crank_length_m, 0):
        errors.append(f"seat height {seat_height_m:g} m must be positive and above the crank "
                      f"length {crank_length_m:g} m (--seat-height-m, or lst + lsp)")
    if errors:
        raise BicycleDataError(f"{source}: " + "; ".join(errors))


def reach_fix(geometry: legs.LegGeometry) -> str:
    """The seat heights at which the legs reach the pedals all round (Sec 2.1.1), as the fix
    to suggest: ``|l_ul - l_ll| + l_cr <= L <= l_ul + l_ll - l_cr``."""
    reach = geometry.shank_length_m + geometry.thigh_length_m
    fold = abs(geometry.thigh_length_m - geometry.shank_length_m)
    lo, hi = fold + geometry.crank_length_m, reach - geometry.crank_length_m
    if lo > hi:
        return (f"no seat height works with a {geometry.crank_length_m:g} m crank: pass a "
                "shorter --crank-length-m")
    return (f"pass --seat-height-m between {np.ceil(lo * 1e3) / 1e3:.3f} and "
            f"{np.floor(hi * 1e3) / 1e3:.3f} m (the book's Rigid example uses 0.72 m, as the "
            "thesis did for the city bicycle, Sec 2.1.1)")


@dataclass(frozen=True)
class OwnBicycle:
    """A bicycle with a rigid rider, ready for the linear analysis.

    Attributes
    ----------
    name, rider
        Bicycle and rider names (folder names).
    benchmark
        Benchmark parameters (Meijaard et al. 2007) of bicycle + rider, SI units.
    model
        The linear model of Eq 3.1 built from ``benchmark``.
    geometry
        The leg geometry driving the pedalling torques (Sec 2.1.1).
    wheel_radius_m
        Rear wheel radius ``rR`` (gear-ratio lines, Sec 3.1.3.2).
    notes
        Choices made while loading (e.g. where the seat geometry came from).
    """

    name: str
    rider: str
    benchmark: dict[str, float]
    model: LinearModel
    geometry: legs.LegGeometry
    wheel_radius_m: float
    notes: tuple[str, ...] = ()

    @property
    def steer_geometry(self) -> dict[str, float]:
        """``w``, ``c``, ``lam`` of the bicycle (the yaw-to-steer factor of Eq 2.15)."""
        return {k: self.benchmark[k] for k in ("w", "c", "lam")}


def _rider_files(data_dir: Path, bicycle: str, rider: str) -> dict[str, Path]:
    rdir = data_dir / "riders" / rider
    return {"meas": rdir / "RawData" / f"{rider}YeadonMeas.txt",
            "cfg": rdir / "RawData" / f"{rider}{bicycle}YeadonCFG.txt",
            "par": rdir / "Parameters" / f"{rider}{bicycle}Benchmark.txt"}


def check_folder(data_dir: str | Path, bicycle: str, rider: str) -> bool:
    """Check that ``data_dir`` holds ``bicycle`` and ``rider`` in BicycleParameters' layout.

    Returns
    -------
    bool
        Whether the rider is to be computed from its Yeadon measurements (``True``) or read
        from a precomputed ``<Rider><Name>Benchmark.txt`` (``False``).

    Raises
    ------
    FileNotFoundError
        Naming every missing folder or file.
    """
    d = Path(data_dir)
    if not d.is_dir():
        raise FileNotFoundError(f"bicycle data folder not found: {d}")
    bdir = d / "bicycles" / bicycle
    if not bdir.is_dir():
        have = sorted(p.name for p in (d / "bicycles").glob("*")) if (d / "bicycles").is_dir() \
            else []
        raise FileNotFoundError(
            f"{d} is not in BicycleParameters' format: missing folder {bdir} "
            f"(bicycles found: {have or 'none'}; expected bicycles/<Name>/Parameters/"
            f"<Name>Benchmark.txt or bicycles/<Name>/RawData/<Name>Measured.txt)")
    bench = bdir / "Parameters" / f"{bicycle}Benchmark.txt"
    measured = bdir / "RawData" / f"{bicycle}Measured.txt"
    if not bench.is_file() and not measured.is_file():
        raise FileNotFoundError(f"bicycle {bicycle!r}: missing both {bench} and {measured} "
                                "(BicycleParameters needs one of them)")
    files = _rider_files(d, bicycle, rider)
    if files["meas"].is_file() and files["cfg"].is_file() and measured.is_file():
        return True
    if files["par"].is_file():
        return False
    missing = [str(p) for p in (files["meas"], files["cfg"], measured) if not p.is_file()]
    raise FileNotFoundError(
        f"rider {rider!r} on bicycle {bicycle!r}: cannot place the rider, missing "
        f"{', '.join(missing)} (or a precomputed {files['par']})")


def seat_geometry(measured: Mapping[str, float] | None, *, seat_height_m: float | None = None,
                  seat_tube_angle_deg: float | None = None) -> tuple[float, float, str]:
    """Hip distance ``L`` from the crank axis along the seat tube and the seat-tube angle.

    ``L = lst + lsp`` and ``lambda_st = lamst`` of BicycleParameters' measured data (as in
    ``legs.yaml`` for the thesis bicycles, Sec 2.1.1), each replaced by an explicit value.

    Returns
    -------
    seat_height_m, seat_tube_angle_rad, note
    """
    measured = dict(measured or {})
    if seat_height_m is None:
        if "lst" not in measured or "lsp" not in measured:
            raise BicycleDataError("the bicycle's measured data (RawData/<Name>Measured.txt) "
                                   "have no 'lst'/'lsp' (seat tube, seat post): pass "
                                   "seat_height_m (--seat-height-m)")
        seat_height_m = float(measured["lst"]) + float(measured["lsp"])
        src = "lst + lsp"
    else:
        src = "given"
    if seat_tube_angle_deg is None:
        if "lamst" not in measured:
            raise BicycleDataError("the bicycle's measured data (RawData/<Name>Measured.txt) "
                                   "have no 'lamst' (seat-tube angle): pass "
                                   "seat_tube_angle_deg (--seat-tube-angle-deg)")
        angle = float(measured["lamst"])
        src_a = "lamst"
    else:
        angle = float(np.deg2rad(seat_tube_angle_deg))
        src_a = "given"
    note = (f"seat: L = {seat_height_m:.4g} m ({src}), seat-tube angle "
            f"{np.rad2deg(angle):.2f} deg ({src_a})")
    return float(seat_height_m), angle, note


def load_bicycle(data_dir: str | Path, bicycle: str, rider: str, *,
                 seat_height_m: float | None = None, seat_tube_angle_deg: float | None = None,
                 crank_length_m: float | None = None, com: str = "O") -> OwnBicycle:
    """Load a bicycle and rider from a BicycleParameters data folder (Sec 3.1.1, Sec 2.1.1).

    Parameters
    ----------
    data_dir
        Folder with ``bicycles/`` and ``riders/`` (see :func:`check_folder`).
    bicycle, rider
        Folder names, e.g. ``"Rigid"`` and ``"Jason"``.
    seat_height_m
        Hip distance from the crank axis along the seat tube (default ``lst + lsp``).
    seat_tube_angle_deg
        Seat-tube angle from the horizontal (default ``lamst``).
    crank_length_m
        Crank length (default ``legs.yaml`` ``crank_length_m``, the thesis's 0.17 m class).
    com
        Leg segment COM fractions, ``"O"`` (homogeneous, the thesis's choice) or ``"W"``.

    Returns
    -------
    OwnBicycle
        Benchmark parameters with the rider added as BicycleParameters does
        (``add_rider(rider, reCalc=True)`` from the Yeadon measurements when present), the
        linear model from ``dtk.bicycle.benchmark_par_to_canonical`` and the leg geometry.
    """
    import bicycleparameters as bp
    from dtk.bicycle import benchmark_par_to_canonical

    d = Path(data_dir)
    recalc = check_folder(d, bicycle, rider)
    # every file read, checked line by line before BicycleParameters parses it
    bdir = d / "bicycles" / bicycle
    files = [p for p in (bdir / "Parameters" / f"{bicycle}Benchmark.txt",
                         bdir / "RawData" / f"{bicycle}Measured.txt") if p.is_file()]
    measured_file = bdir / "RawData" / f"{bicycle}Measured.txt"
    bike_values = {p: check_bicycle_file(p) for p in files}
    rfiles = _rider_files(d, bicycle, rider)
    if recalc:
        read_yeadon_file(rfiles["meas"], positive=True)
        read_yeadon_file(rfiles["cfg"], positive=False)
        rider_files = [rfiles["meas"], rfiles["cfg"]]
    else:
        check_bicycle_file(rfiles["par"])
        rider_files = [rfiles["par"]]
    source = " + ".join(str(p) for p in files[:1] + rider_files)
    # seat and crank (options or the measured file), checked before any computation
    base = legs.leg_geometry("hybrid", com)  # legs.yaml segments; the seat is replaced below
    crank = base.crank_length_m if crank_length_m is None else float(crank_length_m)
    length, angle, note = seat_geometry(bike_values.get(measured_file), seat_height_m=seat_height_m,
                                        seat_tube_angle_deg=seat_tube_angle_deg)
    seat_source = ", ".join(
        [f"--seat-height-m {seat_height_m}" if seat_height_m is not None
         else f"{measured_file}: lst + lsp",
         f"--seat-tube-angle-deg {seat_tube_angle_deg}" if seat_tube_angle_deg is not None
         else f"{measured_file}: lamst",
         f"--crank-length-m {crank_length_m}" if crank_length_m is not None
         else "legs.yaml crank_length_m"])
    check_seat(length, angle, crank, seat_source)
    geometry = replace(base, name=f"{bicycle} + {rider} ({com}), L = {length:g} m",
                       seat_tube_angle_rad=angle, seat_tube_plus_post_m=length,
                       crank_length_m=crank)
    try:
        legs.check_reach(geometry)
    except ValueError as exc:
        raise BicycleDataError(f"{exc} ({seat_source}): {reach_fix(geometry)}") from None
    try:
        with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
            warnings.simplefilter("ignore")
            bike = bp.Bicycle(bicycle, pathToData=str(d))
            bike.add_rider(rider, reCalc=recalc)
            par = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
    except KeyError as exc:
        raise BicycleDataError(f"{' + '.join(map(str, files + rider_files))}: parameter "
                               f"{exc.args[0]!r} missing (BicycleParameters needs it)") from None
    except Exception as exc:  # noqa: BLE001 - any failure inside BicycleParameters/yeadon
        raise BicycleDataError(f"{' + '.join(map(str, files + rider_files))}: BicycleParameters "
                               f"cannot build the bicycle with its rider: "
                               f"{type(exc).__name__}: {exc}") from None
    par = {k: float(v) for k, v in par.items()}
    check_benchmark(par, f"bicycle {bicycle!r} + rider {rider!r} (from {source})")
    m, c1, k0, k2 = benchmark_par_to_canonical(par)
    model = LinearModel(f"{bicycle}+{rider}", *(np.asarray(x, float) for x in (m, c1, k0, k2)),
                        g=float(par.get("g", 9.81)))
    notes = (note, f"crank length {crank:g} m", "leg segments and hip width: legs.yaml",
             "rider: " + ("Yeadon measurements (reCalc)" if recalc else "precomputed parameters"))
    return OwnBicycle(bicycle, rider, par, model, geometry, par["rR"], notes)


def torques(own: OwnBicycle, harmonics: Sequence[int] = (1, 3, 5)) -> disturbance.TorqueHarmonics:
    """Pedalling roll and steer torque harmonics of Eq 3.14 for this bicycle and leg geometry."""
    return disturbance.torque_harmonics(own.name, harmonics=tuple(harmonics),
                                        geometry=own.geometry,
                                        steer_geometry=own.steer_geometry)


@dataclass
class ResonanceMap:
    """PS amplitude at the cadence over a speed x cadence grid (Sec 3.1.2.2.1, Fig 3.35).

    ``roll_amp_rad``/``steer_amp_rad`` are ``(n_v, n_w)``; ``ridge[coord]`` holds, per speed,
    the grid index of the cadence of largest amplitude (the resonance ridge, which follows the
    weave frequency, Fig G.7; -1 where the largest amplitude lies on the edge of the cadence
    grid, where it is no resonance peak, or is zero or NaN); ``inside`` marks the
    points inside the normal-cycling ellipse.
    """

    speed_m_s: np.ndarray
    omega_rad_s: np.ndarray
    roll_amp_rad: np.ndarray
    steer_amp_rad: np.ndarray
    inside: np.ndarray
    ridge: dict[str, np.ndarray] = field(default_factory=dict)


def resonance_map(own: OwnBicycle, speed_m_s: np.ndarray, omega_rad_s: np.ndarray,
                  harmonics: Sequence[int] = (1, 3, 5), *,
                  normal_speed_kmh: Sequence[float] = (14.0, 22.0),
                  normal_cadence_rpm: Sequence[float] = (50.0, 80.0)) -> ResonanceMap:
    """PS cadence amplitudes on a grid (one batched solve, :func:`response.particular_solution`).

    The amplitude at the cadence is that of harmonic ``n = 1`` (as in Fig 3.35); the ridge is the
    cadence of the largest amplitude at each speed.
    """
    v = np.asarray(speed_m_s, float)
    w = np.asarray(omega_rad_s, float)
    h = torques(own, harmonics)
    if 1 not in h.n:
        raise ValueError(f"harmonics must include 1 (the cadence), got {list(harmonics)}")
    k = int(np.nonzero(h.n == 1)[0][0])
    roll, steer = response.particular_solution(own.model, v[:, None], w[None, :], h)
    amps = {"roll": np.abs(roll[..., k]), "steer": np.abs(steer[..., k])}
    inside = gears.inside_ellipse(v[:, None], w[None, :], normal_speed_kmh, normal_cadence_rpm)
    ridge = {}
    for c, a in amps.items():
        a = np.nan_to_num(a, nan=-1.0)
        j = np.argmax(a, axis=1)
        # a maximum on the edge of the cadence grid is not a resonance peak
        ridge[c] = np.where((a.max(axis=1) > 0) & (j > 0) & (j < len(w) - 1), j, -1)
    return ResonanceMap(v, w, amps["roll"], amps["steer"], inside, ridge)


def summary(own: OwnBicycle, rmap: ResonanceMap, eigen_speed_m_s: np.ndarray,
            gear_ratios: Sequence[float] = (1, 2, 3, 4)) -> dict[str, Any]:
    """Eigenvalue speeds (Sec 3.2.1) and where the resonance falls in normal cycling (3.1.3.2).

    Keys: ``weave_speed_m_s``, ``capsize_speed_m_s``, ``stable_from_m_s``, ``stable_to_m_s``,
    ``weave_frequency_at_weave_speed_rad_s``; per ``coord`` in roll/steer: ``<coord>_peak_rad``
    and its ``_speed_m_s``/``_omega_rad_s`` (grid maximum), ``<coord>_normal_peak_rad`` and its
    location (largest amplitude inside the ellipse), ``<coord>_ridge_in_normal_points`` and the
    speed, cadence and gear-ratio ranges of the ridge inside the ellipse (NaN if it misses), and
    ``<coord>_ridge_in_gear_range_*``: the ridge's speeds between the lowest and highest gear
    ratio.
    """
    s = linear.summarise(own.model, np.asarray(eigen_speed_m_s, float))
    out: dict[str, Any] = {"bicycle": own.name, "rider": own.rider,
                           "weave_speed_m_s": s.weave_speed_m_s,
                           "capsize_speed_m_s": s.capsize_speed_m_s,
                           "stable_from_m_s": s.stable_from_m_s, "stable_to_m_s": s.stable_to_m_s,
                           "weave_frequency_at_weave_speed_rad_s":
                               s.weave_frequency_at_weave_speed_rad_s,
                           "wheel_radius_m": own.wheel_radius_m,
                           "seat_height_m": own.geometry.seat_tube_plus_post_m,
                           "crank_length_m": own.geometry.crank_length_m,
                           "gear_ratios": " ".join(f"{g:g}" for g in gear_ratios)}
    v, w = rmap.speed_m_s, rmap.omega_rad_s
    for coord in ("roll", "steer"):
        amp = getattr(rmap, f"{coord}_amp_rad")
        i, j = np.unravel_index(np.nanargmax(amp), amp.shape)
        out |= {f"{coord}_peak_rad": float(amp[i, j]), f"{coord}_peak_speed_m_s": float(v[i]),
                f"{coord}_peak_omega_rad_s": float(w[j])}
        masked = np.where(rmap.inside, amp, -np.inf)
        if rmap.inside.any():
            i, j = np.unravel_index(np.argmax(masked), amp.shape)
            out |= {f"{coord}_normal_peak_rad": float(amp[i, j]),
                    f"{coord}_normal_peak_speed_m_s": float(v[i]),
                    f"{coord}_normal_peak_omega_rad_s": float(w[j])}
        ridge = rmap.ridge[coord]
        rows = np.nonzero(ridge >= 0)[0]
        on = rows[rmap.inside[rows, ridge[rows]]]
        rv, rw = v[on], w[ridge[on]]
        gr = gears.gear_ratio(rv, rw, own.wheel_radius_m)
        out[f"{coord}_ridge_in_normal_points"] = len(on)
        for key, vals in (("speed_m_s", rv), ("omega_rad_s", rw), ("gear_ratio", gr)):
            out[f"{coord}_ridge_in_normal_{key}_min"] = float(vals.min()) if len(on) else np.nan
            out[f"{coord}_ridge_in_normal_{key}_max"] = float(vals.max()) if len(on) else np.nan
        # the ridge within the working range of gear ratios (GR min..max, Sec 3.1.3.2)
        gr_all = gears.gear_ratio(v[rows], w[ridge[rows]], own.wheel_radius_m)
        sel = rows[(gr_all >= min(gear_ratios)) & (gr_all <= max(gear_ratios))]
        out[f"{coord}_ridge_in_gear_range_points"] = len(sel)
        out[f"{coord}_ridge_in_gear_range_speed_m_s_min"] = float(v[sel].min()) if len(sel) \
            else np.nan
        out[f"{coord}_ridge_in_gear_range_speed_m_s_max"] = float(v[sel].max()) if len(sel) \
            else np.nan
    return out


def write_map_csv(path: str | Path, own: OwnBicycle, rmap: ResonanceMap) -> Path:
    """The map in long form: speed, cadence, gear ratio, amplitudes, inside, on-ridge flags."""
    path = Path(path)
    v, w = np.meshgrid(rmap.speed_m_s, rmap.omega_rad_s, indexing="ij")
    on = {c: np.zeros(v.shape, bool) for c in ("roll", "steer")}
    for c, ridge in rmap.ridge.items():
        rows = np.nonzero(ridge >= 0)[0]
        on[c][rows, ridge[rows]] = True
    gr = gears.gear_ratio(v, w, own.wheel_radius_m)
    with path.open("w", newline="") as fh:
        fh.write(f"# PS amplitude at the cadence (harmonic n = 1), {own.name} + rider "
                 f"{own.rider} (pedalrepro.own_bicycle)\n")
        wr = csv.writer(fh)
        wr.writerow(["speed_m_s", "omega_rad_s", "cadence_rpm", "gear_ratio", "roll_amp_rad",
                     "steer_amp_rad", "inside_normal_cycling", "roll_ridge", "steer_ridge"])
        for row in zip(v.ravel(), w.ravel(), w.ravel() * 30 / np.pi, gr.ravel(),
                       rmap.roll_amp_rad.ravel(), rmap.steer_amp_rad.ravel(),
                       rmap.inside.ravel(), on["roll"].ravel(), on["steer"].ravel(), strict=True):
            wr.writerow([f"{x:.12g}" if isinstance(x, float | np.floating) else int(x)
                         for x in row])
    return path


def write_summary_csv(path: str | Path, values: Mapping[str, Any],
                      notes: Sequence[str] = ()) -> Path:
    """The summary as ``key,value`` rows (floats with 12 significant digits)."""
    path = Path(path)
    with path.open("w", newline="") as fh:
        for n in notes:
            fh.write(f"# {n}\n")
        wr = csv.writer(fh)
        wr.writerow(["key", "value"])
        for k, x in values.items():
            val = "" if x is None else (f"{x:.12g}" if isinstance(x, float) else str(x))
            wr.writerow([k, val])
    return path


def plot(own: OwnBicycle, rmap: ResonanceMap, values: Mapping[str, Any],
         normal_speed_kmh: Sequence[float], normal_cadence_rpm: Sequence[float],
         gear_ratios: Sequence[float]):
    """Roll and steer PS maps with gear-ratio lines, normal-cycling ellipse and ridge (Fig 3.35)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .figures.linear import AMP_LEVELS

    fig, axes = plt.subplots(2, 1, figsize=(7, 6.4), sharex=True)  # page width, >= 8 pt text
    v, w = rmap.speed_m_s, rmap.omega_rad_s
    ev, ew = gears.normal_cycling_ellipse(normal_speed_kmh, normal_cadence_rpm)
    w_line = np.linspace(0, w.max(), 50)
    for ax, coord in zip(axes, ("roll", "steer"), strict=True):
        amp = getattr(rmap, f"{coord}_amp_rad")
        # the linear colour scale of the thesis's PS maps (Fig 3.35: AMP_LEVELS, 0-0.04 rad),
        # so the two compare; amplitudes above it (the resonance) take the last colour
        cs = ax.contourf(v, w, amp.T, levels=AMP_LEVELS, extend="max", cmap="viridis")
        cb = fig.colorbar(cs, ax=ax)
        cb.set_label(f"{coord} amplitude (rad)", fontsize=9)
        cb.ax.tick_params(labelsize=8)
        for gr in gear_ratios:
            ax.plot(gears.speed_m_s(gr, w_line, own.wheel_radius_m), w_line, "w--", lw=0.8)
            v_end = float(gears.speed_m_s(gr, w.max(), own.wheel_radius_m))
            at = (v_end, w.max()) if v_end <= v.max() else \
                (v.max(), float(gears.cadence_rad_s(gr, v.max(), own.wheel_radius_m)))
            ax.annotate(f"GR {gr:g}", at, color="w", fontsize=8, ha="right", va="top")
        ax.plot(ev, ew, "w-", lw=1.2, label="normal cycling")
        ridge = rmap.ridge[coord]
        rows = np.nonzero(ridge >= 0)[0]
        ax.plot(v[rows], w[ridge[rows]], "r.", ms=2, label="resonance ridge")
        for key, c in (("weave_speed_m_s", "C1"), ("capsize_speed_m_s", "C3")):
            if values.get(key) is not None:
                ax.axvline(values[key], color=c, lw=0.8, label=key.split("_")[0])
        ax.set_xlim(v.min(), v.max())
        ax.set_ylim(w.min(), w.max())
        ax.set_ylabel("cadence (rad/s)", fontsize=9)
        ax.set_title(f"{own.name} + {own.rider}: {coord}", fontsize=9)
        ax.tick_params(labelsize=8)
    axes[1].set_xlabel("forward speed v (m/s)", fontsize=9)
    axes[0].legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return fig


def run(data_dir: str | Path, bicycle: str, rider: str, out_dir: str | Path,
        lin: Mapping[str, Any], *, png_dir: str | Path | None = None,
        **load_kwargs) -> dict[str, Path]:
    """Load, analyse, and write ``<bicycle>_<rider>_resonance_map.csv``, ``..._summary.csv``
    and ``..._resonance.png`` into ``out_dir`` (the PNG into ``png_dir`` when given).

    ``lin`` holds the keys of config section ``linear`` used here (``ps_*`` grid,
    ``eigen_speed_*``, ``harmonics``, ``gear_ratios``, ``normal_cycling_*``); ``load_kwargs`` go
    to :func:`load_bicycle`.
    """
    own = load_bicycle(data_dir, bicycle, rider, **load_kwargs)
    v, w = response.speed_cadence_grid(lin["ps_speed_step_m_s"], lin["ps_speed_max_m_s"],
                                       lin["ps_omega_step_rad_s"], lin["ps_omega_max_rad_s"])
    rmap = resonance_map(own, v, w, lin["harmonics"],
                         normal_speed_kmh=lin["normal_cycling_speed_kmh"],
                         normal_cadence_rpm=lin["normal_cycling_cadence_rpm"])
    eig_v = response.grid(lin["eigen_speed_step_m_s"], lin["eigen_speed_max_m_s"])[1:]
    values = summary(own, rmap, eig_v, lin["gear_ratios"])
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    stem = out / f"{bicycle}_{rider}"
    paths = {"map": write_map_csv(f"{stem}_resonance_map.csv", own, rmap),
             "summary": write_summary_csv(f"{stem}_summary.csv", values, own.notes)}
    fig = plot(own, rmap, values, lin["normal_cycling_speed_kmh"],
               lin["normal_cycling_cadence_rpm"], lin["gear_ratios"])
    png = Path(png_dir or out) / f"{bicycle}_{rider}_resonance.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    from .figures.page import overlapping_colorbars

    overlaps = overlapping_colorbars(fig)  # as pedalrepro.figures.save checks every figure
    if overlaps:
        raise ValueError(f"{png.name}: " + "; ".join(overlaps))
    fig.savefig(png, dpi=120)
    paths["png"] = png
    return paths


def _cli(args: argparse.Namespace) -> int:
    from . import config

    lin = config.load(args.config)["linear"]
    paths = run(args.bicycle_dir, args.bicycle, args.rider, args.out, lin,
                seat_height_m=args.seat_height_m, seat_tube_angle_deg=args.seat_tube_angle_deg,
                crank_length_m=args.crank_length_m)
    for p in paths.values():
        print(p)
    return 0


def add_cli(subparsers) -> None:
    """Register ``pedalrepro resonance BICYCLE_DIR --bicycle NAME --rider RIDER [--out DIR]``."""
    p = subparsers.add_parser("resonance", help="pedalling resonance map of your own bicycle "
                              "(BicycleParameters data folder)")
    p.add_argument("bicycle_dir", help="folder with bicycles/<NAME>/ and riders/<RIDER>/")
    p.add_argument("--bicycle", required=True, help="bicycle folder name, e.g. Rigid")
    p.add_argument("--rider", required=True, help="rider folder name, e.g. Jason")
    p.add_argument("--out", default=".", help="output folder (default: current)")
    p.add_argument("--seat-height-m", type=float, default=None,
                   help="hip distance from the crank axis along the seat tube (default lst+lsp)")
    p.add_argument("--seat-tube-angle-deg", type=float, default=None,
                   help="seat-tube angle from the horizontal (default lamst)")
    p.add_argument("--crank-length-m", type=float, default=None,
                   help="crank length (default legs.yaml)")
    p.add_argument("--config", default=None, help="config file (default config/config.yaml)")
    p.set_defaults(func=_cli)
