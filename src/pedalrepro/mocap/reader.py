"""Reader of the published per-run MATLAB files of the treadmill data (Sec 4.1).

Format (evidence: moorepants/MotionCapture ``PythonCode/mat2npy.py``, ``fixGaps.py``,
``states.py``, ``MatlabCode/convertData.m``; summarised in the book's validation chapter):

- one file per run, ``RNNN.mat``: ``R`` = rider digit (1, 2, 3), ``NNN`` = trial (001-110);
  trials 001 and 051 are the static runs (Stratos and Browser);
- ``t`` (N x 1, s); ``x``, ``y``, ``z`` (N x 31, gap-repaired marker coordinates);
  ``xori``, ``yori``, ``zori`` (N x 31, raw, with gaps); ``bike`` (``'stratos'`` or
  ``'browser'``); ``condition`` (task); ``V`` (belt speed, km/h); ``gearing`` (riders 2, 3) or
  ``gear`` (rider 1). Static runs hold only ``x``, ``y``, ``z``;
- coordinates in the Optotrak frame M (m1 forward, m2 to the rider's left, m3 up, belt at
  m3 = 0), metres for the dynamic runs and millimetres for the static runs.

:func:`read_run` returns the markers in the benchmark frame N = diag(1, -1, -1) M (x forward,
y right, z down; Meijaard et al. 2007) in metres. Missing samples become NaN: NaN in the file,
the camera system's sentinel ``|value| > 1e20``, and exact zeros in the raw ``xori`` arrays
(a marker at the lab origin is impossible: the origin lies on the belt under the bicycle).
"""

from __future__ import annotations

import re
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.io

__all__ = [
    "MARKERS", "N_MARKERS", "FORK_MARKERS", "REAR_FRAME_MARKERS", "WHEEL_CENTRE_MARKERS",
    "SENTINEL", "MM_THRESHOLD", "M_TO_N", "TASKS", "BICYCLES", "MocapFileError", "marker_index",
    "parse_run_id", "task_of", "runs_rider", "Run", "FORMATS", "EXPORT_SUFFIXES", "EXPORT_NAME",
    "is_export", "check_mat_name", "read_run", "read_metadata",
]

#: Marker names, index = marker number - 1 (autolev/MOCAP.AL, convertData.m; 25 is the right
#: rear wheel centre per MOCAP.AL and sign checks, the dissertation text swaps 25 and 31).
MARKERS: tuple[str, ...] = (
    "right_foot", "right_ankle", "right_knee", "right_hip", "left_foot", "left_ankle",
    "left_knee", "left_hip", "coccyx", "l1", "t6", "helmet_back", "right_wrist", "right_elbow",
    "right_shoulder", "right_temple", "left_wrist", "left_elbow", "left_shoulder", "left_temple",
    "right_front_wheel", "right_head_tube", "right_handlebar", "right_seat_stay",
    "right_rear_wheel", "seat_post", "left_front_wheel", "left_head_tube", "left_handlebar",
    "left_seat_stay", "left_rear_wheel",
)
N_MARKERS = len(MARKERS)
#: Marker numbers (1-based, as published) of the two rigid bodies.
FORK_MARKERS: tuple[int, ...] = (21, 23, 27, 29)
REAR_FRAME_MARKERS: tuple[int, ...] = (22, 24, 25, 26, 28, 30, 31)
WHEEL_CENTRE_MARKERS: tuple[int, ...] = (21, 25, 27, 31)
#: Values beyond this magnitude are the camera system's missing-value sentinel.
SENTINEL = 1e20
#: Wheel-centre height (lab z, up) above which a file is taken to be in millimetres; the wheel
#: centres are about 0.34 m (dynamic runs, metres) or 340 (static runs, millimetres) high.
MM_THRESHOLD = 10.0
#: Optotrak frame M -> benchmark frame N (convertData.m: n1 = m1, n2 = -m2, n3 = -m3).
M_TO_N = np.array([1.0, -1.0, -1.0])

TASKS: tuple[str, ...] = ("pedalling", "towing", "nohands", "linetracking", "static", "unknown")
BICYCLES: dict[str, str] = {"stratos": "hybrid", "browser": "city"}


class MocapFileError(ValueError):
    """A run file that cannot be read as the published format (the message names the file)."""


def marker_index(number: int) -> int:
    """0-based column of a 1-based published marker number."""
    if not 1 <= int(number) <= N_MARKERS:
        raise ValueError(f"marker number {number} outside 1..{N_MARKERS}")
    return int(number) - 1


def parse_run_id(name: str | int | Path) -> tuple[int, int, int]:
    """Run id ``RNNN`` -> ``(run_id, rider, trial)``, from a number or a file name.

    Raises
    ------
    ValueError
        When the name is not four digits with rider 1-3 and trial 1-110.
    """
    stem = Path(str(name)).stem if not isinstance(name, int) else f"{name:04d}"
    m = re.fullmatch(r"(\d)(\d{3})", stem)
    if not m:
        raise ValueError(f"{name!r} is not a run number RNNN (rider digit + 3-digit trial)")
    rider, trial = int(m.group(1)), int(m.group(2))
    if rider not in (1, 2, 3) or not 1 <= trial <= 110:
        raise ValueError(
            f"unknown run {stem}: riders are 1-3 and trials 001-110 (Moore et al. 2014)")
    return int(stem), rider, trial


def task_of(condition: str, rider: int, trial: int) -> str:
    """Normalised task name from the ``condition`` string (case-insensitive substrings).

    Only ``'nohands'`` and ``'static'`` are attested in the public sources; the other strings are
    matched on substrings (``tow``, ``line``, ``pedal``/``normal``) and, failing that, on the
    trial numbers of rider 3 (``validation_runs.yaml`` ``task_by_trial``, from
    ``percentageplot.m`` and ``lateral.py``).
    """
    c = condition.lower().replace(" ", "").replace("-", "").replace("_", "")
    for key, task in (("static", "static"), ("nohand", "nohands"), ("handsfree", "nohands"),
                      ("tow", "towing"), ("line", "linetracking"), ("pedal", "pedalling"),
                      ("normal", "pedalling")):
        if key in c:
            return task
    runs = _runs_table()
    if trial in runs["static_trials"].values():
        return "static"
    if rider == int(runs_rider()):
        for task, ranges in runs["task_by_trial"].items():
            if any(lo <= trial <= hi for lo, hi in ranges):
                return task
    return "unknown"


def _runs_table() -> dict:
    from .. import params, paths

    return params.read_yaml(paths.PARAMETERS / "validation_runs.yaml")["runs"]


def runs_rider() -> int:
    """The rider of the thesis's runs (``validation_runs.yaml``: rider 3)."""
    from .. import params, paths

    return int(params.read_yaml(paths.PARAMETERS / "validation_runs.yaml")["rider"])


@dataclass
class Run:
    """One treadmill run: metadata and marker trajectories (SI units, benchmark frame N).

    Attributes
    ----------
    run_id, rider, trial
        ``RNNN`` and its parts.
    bicycle
        ``"stratos"`` (hybrid; models HS, HR) or ``"browser"`` (city; models CF, CR).
    task
        One of :data:`TASKS`; ``condition`` keeps the string of the file.
    speed_kmh
        Belt speed ``V`` (km/h); NaN for a static run.
    gear
        ``gearing`` / ``gear`` as a string (hub gear index or ``'none'``).
    t_s
        Sample times (s), shape ``(N,)``.
    markers_m
        Gap-repaired markers ``x, y, z`` of the file, shape ``(N, 31, 3)``, NaN where missing.
    raw_m
        Raw markers ``xori, yori, zori``, same shape (a copy of ``markers_m`` when absent).
    notes
        Repairs applied while reading (unit conversion, sentinels, missing variables).
    """

    run_id: int
    rider: int
    trial: int
    bicycle: str
    task: str
    condition: str
    speed_kmh: float
    gear: str
    t_s: np.ndarray
    markers_m: np.ndarray
    raw_m: np.ndarray
    source: Path | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def speed_m_s(self) -> float:
        return self.speed_kmh / 3.6

    @property
    def sample_rate_hz(self) -> float:
        return float(1.0 / np.median(np.diff(self.t_s)))

    @property
    def is_static(self) -> bool:
        return self.task == "static"

    @property
    def bicycle_kind(self) -> str:
        """``"hybrid"`` or ``"city"`` (the names of :mod:`pedalrepro.params`)."""
        return BICYCLES[self.bicycle]

    def marker(self, number: int, raw: bool = False) -> np.ndarray:
        """Trajectory ``(N, 3)`` of a published (1-based) marker number."""
        return (self.raw_m if raw else self.markers_m)[:, marker_index(number), :]


def _string(value, name: str, path: Path) -> str:
    arr = np.asarray(value)
    if arr.dtype.kind in "US":
        return "".join(str(s) for s in arr.ravel()).strip()
    if arr.size == 0:
        return ""
    if arr.dtype.kind in "iuf" and arr.size == 1:
        v = float(arr.ravel()[0])
        return str(int(v)) if v.is_integer() else str(v)
    raise MocapFileError(f"{path}: variable {name!r} is not a string ({arr.dtype}, {arr.shape})")


def _coordinates(data: dict, names: tuple[str, str, str], path: Path,
                 n_samples: int | None) -> np.ndarray:
    arrays = []
    for name in names:
        a = np.asarray(data[name], dtype=float)
        if a.ndim != 2:
            raise MocapFileError(f"{path}: {name!r} must be samples x markers, got {a.shape}")
        if a.shape[1] != N_MARKERS and a.shape[0] == N_MARKERS:
            a = a.T
        if a.shape[1] != N_MARKERS:
            raise MocapFileError(
                f"{path}: {name!r} has {a.shape[1]} marker columns, the published format has "
                f"{N_MARKERS}")
        arrays.append(a)
    shapes = {a.shape for a in arrays}
    if len(shapes) != 1:
        raise MocapFileError(f"{path}: {names} have different shapes {sorted(shapes)}")
    xyz = np.stack(arrays, axis=-1)
    if n_samples is not None and xyz.shape[0] != n_samples:
        raise MocapFileError(
            f"{path}: {names[0]!r} has {xyz.shape[0]} samples but t has {n_samples} "
            "(truncated file?)")
    return xyz


def _missing_to_nan(xyz: np.ndarray, zeros_missing: bool) -> tuple[np.ndarray, int]:
    xyz = xyz.copy()
    bad = ~np.isfinite(xyz) | (np.abs(xyz) > SENTINEL)
    n_sentinel = int(np.sum(np.isfinite(xyz) & (np.abs(xyz) > SENTINEL)))
    if zeros_missing:
        bad |= np.all(xyz == 0.0, axis=-1, keepdims=True)
    # a marker is missing as a whole point: one bad coordinate hides the other two
    bad = np.any(bad, axis=-1, keepdims=True)
    xyz[np.broadcast_to(bad, xyz.shape)] = np.nan
    return xyz, n_sentinel


#: What the project reads, for error messages.
FORMATS = ("the published run files RNNN.mat (MATLAB v5: t, x, y, z, xori, yori, zori, bike, "
           "condition, V, gearing), or per-coordinate exports RNNN_X/Y/Z as .xlsx or .csv "
           "(pedalrepro.mocap.exports; `pedalrepro mocap extract RNNN_X.xlsx` finds the Y and Z "
           "files beside it, `pedalrepro mocap import` converts them to RNNN.mat)")


#: Suffixes of the per-coordinate exports (:mod:`pedalrepro.mocap.exports`).
EXPORT_SUFFIXES: tuple[str, ...] = (".xlsx", ".csv")
#: File-name stem of an export: run number, optional separator, coordinate letter.
EXPORT_NAME = re.compile(r"^(?P<run>\d{4})[_\- ]?(?P<coord>[XYZxyz])$")


def is_export(path: str | Path) -> bool:
    """True for a file name of a per-coordinate export (``3045_X.xlsx``, ``3101Y.csv``)."""
    p = Path(path)
    return p.suffix.lower() in EXPORT_SUFFIXES and EXPORT_NAME.match(p.stem) is not None


def check_mat_name(path: Path) -> None:
    """A clear error when ``path`` is not a ``.mat`` file (e.g. an export passed instead)."""
    if path.suffix.lower() == ".mat":
        return
    kind = ("a per-coordinate export (one coordinate of every marker), not a run file"
            if is_export(path) else f"not a run file (suffix {path.suffix or 'none'!r})")
    raise MocapFileError(f"{path}: {kind}. Read are: {FORMATS}.")


def read_run(path: str | Path, sample_rate_hz: float = 100.0) -> Run:
    """Read one published run file ``RNNN.mat`` into a :class:`Run` (SI, benchmark frame).

    Parameters
    ----------
    path
        The file; its stem must be the run number ``RNNN``.
    sample_rate_hz
        Used only to build the time base of a static run (which has no ``t``).

    Raises
    ------
    MocapFileError
        Unreadable, truncated or corrupt file, a MATLAB v7.3 (HDF5) file, missing marker
        variables, or arrays of the wrong shape; the message names the file.
    ValueError
        A file name that is not a run number (see :func:`parse_run_id`).

    Notes
    -----
    Documented repairs (listed in ``Run.notes``): millimetres -> metres when the median
    wheel-centre height exceeds :data:`MM_THRESHOLD` (the static runs); sentinels and NaN ->
    NaN; all-zero raw points -> NaN; a dynamic run without ``xori`` uses the repaired arrays
    as raw; ``gear`` (rider 1) is read like ``gearing``.
    """
    path = Path(path)
    check_mat_name(path)
    run_id, rider, trial = parse_run_id(path)
    if not path.is_file():
        raise FileNotFoundError(f"run file not found: {path}")
    data = _load_mat(path)
    notes: list[str] = []
    t, xyz, raw = _time_and_markers(data, path, sample_rate_hz, notes)
    xyz, raw = _repair_markers(xyz, raw, path, notes)

    condition = _string(data["condition"], "condition", path) if "condition" in data else ""
    task = task_of(condition, rider, trial)
    if "condition" not in data and task != "static":
        notes.append("no condition: task from the run number")
    bike = _bicycle(data, path, trial, notes)
    speed = _belt_speed(data, path, task)
    gear_var = "gearing" if "gearing" in data else ("gear" if "gear" in data else None)
    gear = _string(data[gear_var], gear_var, path) if gear_var else "none"
    if task != "static" and raw is not None and "xori" not in data:
        notes.append("no xori/yori/zori: the repaired x, y, z serve as raw")
    return Run(run_id=run_id, rider=rider, trial=trial, bicycle=bike, task=task,
               condition=condition, speed_kmh=speed, gear=gear, t_s=t, markers_m=xyz,
               raw_m=raw, source=path, notes=notes)


def _load_mat(path: Path) -> dict:
    """The variables of a MATLAB v5 file.

    Parameters
    ----------
    path
        The run file.

    Returns
    -------
    dict
        :func:`scipy.io.loadmat` of the file (arrays not squeezed).

    Raises
    ------
    MocapFileError
        A MATLAB v7.3 (HDF5) file, or one that cannot be read (corrupt or truncated).
    """
    try:
        return scipy.io.loadmat(str(path), squeeze_me=False, mat_dtype=False)
    except NotImplementedError as exc:  # MATLAB v7.3 = HDF5
        raise MocapFileError(
            f"{path}: MATLAB v7.3 (HDF5) file; the published runs are v5 files ({exc})") from exc
    except (ValueError, TypeError, OSError, EOFError, IndexError, KeyError, AttributeError,
            UnicodeDecodeError, zipfile.BadZipFile) as exc:
        raise MocapFileError(f"{path}: cannot read as a MATLAB file (corrupt or truncated?): "
                             f"{type(exc).__name__}: {exc}") from exc
    except Exception as exc:  # scipy raises many private error types on damaged streams
        raise MocapFileError(f"{path}: cannot read as a MATLAB file (corrupt or truncated?): "
                             f"{type(exc).__name__}: {exc}") from exc


def _time_and_markers(data: dict, path: Path, sample_rate_hz: float,
                      notes: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The time base and the repaired and raw marker arrays of a run file, as stored.

    Parameters
    ----------
    data
        The file's variables (:func:`_load_mat`).
    path
        The run file, named in the messages.
    sample_rate_hz
        The time base of a file without ``t``.
    notes
        The run's repair notes, appended to.

    Returns
    -------
    tuple of numpy.ndarray
        ``t`` (s), then ``x, y, z`` and ``xori, yori, zori`` (or a copy of ``x, y, z`` without
        them), each n x markers x 3, in the file's units and frame.

    Raises
    ------
    MocapFileError
        Missing ``x, y, z``, arrays of the wrong shape, or ``t`` not strictly increasing.
    """
    missing = [v for v in ("x", "y", "z") if v not in data]
    if missing:
        raise MocapFileError(f"{path}: marker variables {missing} missing (expected t, x, y, z, "
                             "xori, yori, zori, bike, condition, V, gearing)")
    n_t = None
    if "t" in data:
        t = np.asarray(data["t"], dtype=float).ravel()
        n_t = t.size
    xyz = _coordinates(data, ("x", "y", "z"), path, n_t)
    if n_t is None:
        t = np.arange(xyz.shape[0]) / sample_rate_hz
        notes.append(f"no t: time base from {sample_rate_hz:g} Hz")
    if t.size < 2 or not np.all(np.diff(t) > 0):
        raise MocapFileError(f"{path}: t is not strictly increasing")
    if all(v in data for v in ("xori", "yori", "zori")):
        raw = _coordinates(data, ("xori", "yori", "zori"), path, t.size)
    else:
        raw = xyz.copy()
    return t, xyz, raw


def _repair_markers(xyz: np.ndarray, raw: np.ndarray, path: Path,
                    notes: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """The marker arrays with sentinels as NaN, in metres and the benchmark frame.

    Parameters
    ----------
    xyz, raw
        The repaired and raw arrays as stored (:func:`_time_and_markers`).
    path
        The run file, named in the messages.
    notes
        The run's repair notes, appended to.

    Returns
    -------
    tuple of numpy.ndarray
        ``xyz`` and ``raw``: sentinels and NaN -> NaN (and all-zero raw points), millimetres ->
        metres per array when the median wheel-centre height exceeds :data:`MM_THRESHOLD`, then
        :data:`M_TO_N` applied.

    Raises
    ------
    MocapFileError
        If no wheel-centre marker is ever visible.
    """
    xyz, n_sent = _missing_to_nan(xyz, zeros_missing=False)
    raw, n_sent_raw = _missing_to_nan(raw, zeros_missing=True)
    if n_sent or n_sent_raw:
        notes.append(f"{n_sent + n_sent_raw} sentinel values (|v| > {SENTINEL:g}) -> NaN")

    wheels = [marker_index(m) for m in WHEEL_CENTRE_MARKERS]
    if np.all(np.isnan(xyz[:, wheels, 2])):
        raise MocapFileError(f"{path}: no wheel-centre marker (21, 25, 27, 31) is ever visible")
    # units per array (the repaired and the raw arrays are checked separately)
    for name, arr in (("x, y, z", xyz), ("xori, yori, zori", raw)):
        h = arr[:, wheels, 2]
        if np.any(np.isfinite(h)) and np.nanmedian(h) > MM_THRESHOLD:
            arr /= 1000.0
            notes.append(f"{name}: millimetres -> metres (wheel-centre height)")
    xyz *= M_TO_N
    raw *= M_TO_N
    return xyz, raw


def _bicycle(data: dict, path: Path, trial: int, notes: list[str]) -> str:
    """The run's bicycle: ``bike`` (lower case), or for a static run without it, its trial's.

    Parameters
    ----------
    data
        The file's variables (:func:`_load_mat`).
    path
        The run file, named in the messages.
    trial
        The trial number (:func:`parse_run_id`).
    notes
        The run's repair notes, appended to.

    Returns
    -------
    str
        One of :data:`BICYCLES`.

    Raises
    ------
    MocapFileError
        If ``bike`` is not a string or not one of :data:`BICYCLES` (and the run is not a
        static trial without it).
    """
    bike = _string(data["bike"], "bike", path).lower() if "bike" in data else ""
    if bike not in BICYCLES:
        static = {int(t): b for b, t in _runs_table()["static_trials"].items()}
        if trial in static and not bike:
            bike = static[trial]
            notes.append("no bike: static run bicycle from the trial number")
        else:
            raise MocapFileError(f"{path}: bike {bike!r} is not one of {sorted(BICYCLES)}")
    return bike


def _belt_speed(data: dict, path: Path, task: str) -> float:
    """The belt speed ``V`` (km/h); NaN for a static run without it.

    Parameters
    ----------
    data
        The file's variables (:func:`_load_mat`).
    path
        The run file, named in the messages.
    task
        The run's task (:func:`task_of`).

    Returns
    -------
    float

    Raises
    ------
    MocapFileError
        If ``V`` is not a number, is negative or not finite, or is missing in a dynamic run.
    """
    if "V" in data:
        try:
            speed = float(np.asarray(data["V"], dtype=float).ravel()[0])
        except (ValueError, TypeError, IndexError) as exc:
            raise MocapFileError(f"{path}: belt speed V is not a number: {data['V']!r}") from exc
        if not np.isfinite(speed) or speed < 0:
            raise MocapFileError(f"{path}: belt speed V = {speed} km/h")
        return speed
    if task == "static":
        return float("nan")
    raise MocapFileError(f"{path}: belt speed V (km/h) missing in a {task} run")


def read_metadata(path: str | Path) -> dict:
    """Only the metadata of a run file (fast: the marker arrays are not converted).

    Returns a dict with ``run_id, rider, trial, bicycle, task, condition, speed_kmh, gear,
    n_samples, file``.
    """
    path = Path(path)
    check_mat_name(path)
    run_id, rider, trial = parse_run_id(path)
    try:
        data = scipy.io.loadmat(str(path), variable_names=["bike", "condition", "V", "gearing",
                                                           "gear", "t"])
    except Exception as exc:
        raise MocapFileError(f"{path}: cannot read as a MATLAB file (corrupt or truncated?): "
                             f"{type(exc).__name__}: {exc}") from exc
    condition = _string(data["condition"], "condition", path) if "condition" in data else ""
    gear_var = "gearing" if "gearing" in data else ("gear" if "gear" in data else None)
    return {
        "run_id": run_id, "rider": rider, "trial": trial,
        "bicycle": _string(data["bike"], "bike", path).lower() if "bike" in data else "",
        "task": task_of(condition, rider, trial), "condition": condition,
        "speed_kmh": float(np.asarray(data["V"], float).ravel()[0]) if "V" in data else np.nan,
        "gear": _string(data[gear_var], gear_var, path) if gear_var else "none",
        "n_samples": int(np.asarray(data["t"]).size) if "t" in data else 0,
        "file": str(path),
    }
