"""Reader of per-coordinate exports of the treadmill runs (``RNNN_X.xlsx``, ``RNNNY.csv``, ...).

A public subset of the real recordings (Moore, Kooijman & Schwab 2014, figshare DOI
10.6084/m9.figshare.1082512) is re-hosted as one spreadsheet or CSV file per coordinate by the
repository ``mechmotum/no-hands-riding`` (registry ``data/registry_public.txt``, metadata
``data/parameters/public_runs.yaml``). Layout of those files (checked on the files):

- one coordinate of the Optotrak frame M per file (x forward, y to the rider's left, z up,
  metres), rows = samples at 100 Hz, columns = markers 1-31 in the published order
  (:data:`pedalrepro.mocap.reader.MARKERS`), no header, missing samples ``NaN``;
- an x file may carry the **belt distance**: 33 columns, columns 1-31 = marker x plus the belt
  distance, column 32 empty, column 33 = the belt distance itself (m). The raw x is columns
  1-31 minus column 33, and the belt speed is the slope of column 33 (0.0694444 m per sample at
  100 Hz = 25.0 km/h for run 3045);
- ``.xlsx`` (Office Open XML, read with ``python-calamine``, the Python binding of the Rust
  spreadsheet reader calamine) or ``.csv`` (``;`` or ``,`` separated, optional UTF-8 byte-order
  mark).

No metadata travels with the files: bicycle, task and rider come from the committed table
``data/parameters/public_runs.yaml`` (which cites the evidence for each entry), the belt speed
from the belt-distance column when present, else from that table.

:func:`read_export_run` returns the same :class:`~pedalrepro.mocap.reader.Run` as
:func:`~pedalrepro.mocap.reader.read_run` (SI units, benchmark frame N = diag(1, -1, -1) M);
the exports hold raw coordinates only, so ``raw_m`` and ``markers_m`` are the same array.
:func:`write_mat` writes a run in the published ``RNNN.mat`` layout (``pedalrepro mocap
import``).
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import python_calamine

from .. import params, paths
from .reader import (
    BICYCLES,
    EXPORT_NAME,
    EXPORT_SUFFIXES,
    M_TO_N,
    N_MARKERS,
    MocapFileError,
    Run,
    is_export,
    parse_run_id,
)

__all__ = [
    "PUBLIC_RUNS", "IncompleteRunError", "export_parts", "read_xlsx", "read_csv", "read_table",
    "public_runs", "run_metadata", "sibling_files", "read_export_run", "write_mat",
]

PUBLIC_RUNS: Path = paths.PARAMETERS / "public_runs.yaml"


class IncompleteRunError(MocapFileError):
    """A run whose exports lack a coordinate file (the message names what is missing)."""


def export_parts(path: str | Path) -> tuple[int, str]:
    """``(run_id, coordinate)`` of an export file name, e.g. ``3045_X.xlsx`` -> (3045, "x")."""
    p = Path(path)
    m = EXPORT_NAME.match(p.stem)
    if p.suffix.lower() not in EXPORT_SUFFIXES or m is None:
        raise MocapFileError(
            f"{p}: not a per-coordinate export: expected RNNN_X.xlsx / RNNNY.csv (run number, "
            f"coordinate X, Y or Z, suffix {' or '.join(EXPORT_SUFFIXES)})")
    return int(m.group("run")), m.group("coord").lower()


def read_xlsx(path: str | Path) -> np.ndarray:
    """The first worksheet of an ``.xlsx`` file as a float array (empty cell or text -> NaN).

    Read with ``python-calamine``: numeric cells are the float64 of the stored decimal text (the
    same bits as ``float(text)``), text cells (``NaN`` in the exports) and empty cells become
    NaN; the array spans row 1 and column A to the last used cell, as the sheet is laid out.
    """
    path = Path(path)
    try:
        workbook = python_calamine.CalamineWorkbook.from_path(str(path))
        if not workbook.sheet_names:
            raise MocapFileError(f"{path}: no worksheet in this .xlsx file")
        rows = workbook.get_sheet_by_index(0).to_python(skip_empty_area=False)
    except python_calamine.CalamineError as exc:
        raise MocapFileError(f"{path}: not a readable .xlsx file (corrupt or truncated?): "
                             f"{type(exc).__name__}: {exc}") from exc
    if not rows or not any(rows):
        raise MocapFileError(f"{path}: the worksheet is empty")
    out = np.full((len(rows), max(len(r) for r in rows)), np.nan)
    for i, row in enumerate(rows):
        for j, value in enumerate(row):
            if isinstance(value, float | int) and not isinstance(value, bool):
                out[i, j] = value
    return out


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return float("nan")


def read_csv(path: str | Path) -> np.ndarray:
    """A ``;``- or ``,``-separated numeric CSV without header (BOM tolerated; ``NaN`` -> NaN)."""
    path = Path(path)
    text = path.read_bytes().decode("utf-8-sig", errors="strict")
    first = text.split("\n", 1)[0]
    delim = ";" if first.count(";") >= first.count(",") else ","
    rows = [[_number(c.strip()) if c.strip() else float("nan") for c in row]
            for row in csv.reader(io.StringIO(text), delimiter=delim) if row]
    if not rows:
        raise MocapFileError(f"{path}: empty CSV file")
    width = max(len(r) for r in rows)
    return np.array([r + [float("nan")] * (width - len(r)) for r in rows], dtype=float)


def read_table(path: str | Path) -> np.ndarray:
    """One export file as samples x columns (``.xlsx`` or ``.csv``)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"export file not found: {path}")
    if path.suffix.lower() == ".xlsx":
        return read_xlsx(path)
    if path.suffix.lower() == ".csv":
        return read_csv(path)
    raise MocapFileError(f"{path}: exports are read as {' or '.join(EXPORT_SUFFIXES)}")


def public_runs() -> dict:
    """``data/parameters/public_runs.yaml``: metadata of the public subset's runs."""
    return params.read_yaml(PUBLIC_RUNS)


def run_metadata(run_id: int) -> dict:
    """Metadata of one exported run from the committed table (clear error when not listed)."""
    runs = public_runs()["runs"]
    if int(run_id) not in runs:
        raise MocapFileError(
            f"run {run_id}: no metadata (bicycle, task, belt speed) for it in {PUBLIC_RUNS}; "
            f"the exports carry none. Listed runs: {sorted(runs)}")
    return dict(runs[int(run_id)])


def sibling_files(path: str | Path) -> dict[str, Path]:
    """The X, Y, Z exports of the run of ``path`` found next to it (any naming/suffix)."""
    path = Path(path)
    run_id, _ = export_parts(path)
    found: dict[str, Path] = {}
    for p in sorted(path.parent.iterdir()):
        if is_export(p):
            rid, coord = export_parts(p)
            if rid == run_id:
                found.setdefault(coord, p)
    return found


def _check_files(run_id: int, files: dict[str, Path]) -> None:
    missing = [c for c in "xyz" if c not in files]
    if missing:
        have = ", ".join(f"{c}: {files[c].name}" for c in sorted(files)) or "none"
        need = {"x": "forward positions and, in the published exports, the belt distance",
                "y": "lateral positions", "z": "heights"}
        what = " and the ".join(f"{c.upper()} file ({need[c]})" for c in missing)
        raise IncompleteRunError(
            f"run {run_id}: incomplete export, the {what} is missing "
            f"(found {have}; expected {run_id}_X, {run_id}_Y, {run_id}_Z as .xlsx or .csv). "
            "Roll, yaw and steer need the rear frame's and the fork's orientation in 3-D and the "
            "crank angle needs the feet's forward position: without the x coordinate the run "
            "cannot be analysed (a roll-only estimate from y and z would mix in yaw, so none is "
            "offered)")


def read_export_run(files: dict[str, str | Path] | list[str | Path] | str | Path,
                    metadata: dict | None = None, sample_rate_hz: float | None = None) -> Run:
    """Read a run from its per-coordinate exports into a :class:`Run` (SI, benchmark frame).

    Parameters
    ----------
    files
        The three exports (a dict ``{"x": path, "y": path, "z": path}``, a list of paths named
        ``RNNN_X...``), or one of them (its siblings are looked up in the same folder).
    metadata
        ``bicycle, task, condition, rider, speed_kmh, gear, sample_rate_hz``; default the
        committed table :data:`PUBLIC_RUNS`.
    sample_rate_hz
        Overrides the table's sample rate (100 Hz for the published runs).

    Raises
    ------
    IncompleteRunError
        A coordinate file is missing (names which and why the run cannot be analysed).
    MocapFileError
        Unreadable file, wrong number of marker columns, files of different lengths, or a run
        without metadata.
    """
    if isinstance(files, (str, Path)):
        files = sibling_files(files)
    if not isinstance(files, dict):
        d: dict[str, Path] = {}
        for p in files:
            rid_, c = export_parts(p)
            d[c] = Path(p)
        files = d
    files = {k.lower(): Path(v) for k, v in files.items()}
    ids = {export_parts(p)[0] for p in files.values()}
    if len(ids) != 1:
        raise MocapFileError(f"exports of different runs given together: {sorted(ids)}")
    run_id = ids.pop()
    run_id, rider_from_id, trial = parse_run_id(run_id)
    _check_files(run_id, files)
    meta = {**run_metadata(run_id)} if metadata is None else dict(metadata)
    fs = float(sample_rate_hz or meta.get("sample_rate_hz", 100.0))
    names = ", ".join(p.name for p in files.values())
    notes: list[str] = [f"read from per-coordinate exports ({names}); metadata from the "
                        f"table {PUBLIC_RUNS.name}"]
    arrays, belt = {}, None
    for c in "xyz":
        a = read_table(files[c])
        if a.shape[1] == N_MARKERS + 2 and c == "x":
            belt = a[:, N_MARKERS + 1]
            if not np.all(np.isnan(a[:, N_MARKERS])):
                raise MocapFileError(f"{files[c]}: 33 columns but column 32 is not empty: not "
                                     "the belt-distance layout (markers 1-31, empty, belt)")
            if not np.all(np.isfinite(belt)):
                raise MocapFileError(f"{files[c]}: the belt distance (column 33) has gaps")
            a = a[:, :N_MARKERS] - belt[:, None]
            notes.append("x = columns 1-31 minus the belt distance (column 33)")
        elif a.shape[1] != N_MARKERS:
            raise MocapFileError(
                f"{files[c]}: {a.shape[1]} columns; a coordinate export has {N_MARKERS} "
                f"(markers 1-{N_MARKERS}), or {N_MARKERS + 2} for an x file with the belt "
                "distance")
        arrays[c] = a
    lengths = {c: a.shape[0] for c, a in arrays.items()}
    if len(set(lengths.values())) != 1:
        raise MocapFileError(f"run {run_id}: exports of different lengths {lengths} "
                             "(truncated file?)")
    xyz = np.stack([arrays["x"], arrays["y"], arrays["z"]], axis=-1)
    bad = np.any(~np.isfinite(xyz), axis=-1, keepdims=True)
    xyz[np.broadcast_to(bad, xyz.shape)] = np.nan
    xyz *= M_TO_N
    t = np.arange(xyz.shape[0]) / fs
    speed = float(meta.get("speed_kmh", np.nan))
    if belt is not None:
        v_belt = float(np.polyfit(t, belt, 1)[0]) * 3.6
        if np.isfinite(speed) and abs(abs(v_belt) - speed) > 0.05:
            raise MocapFileError(
                f"run {run_id}: belt speed {abs(v_belt):.3f} km/h from the belt distance differs "
                f"from {speed} km/h in {PUBLIC_RUNS.name}")
        speed = abs(v_belt)
        notes.append(f"belt speed {speed:.4f} km/h from the belt-distance column")
    if not np.isfinite(speed):
        raise MocapFileError(f"run {run_id}: no belt speed (no belt-distance column and none in "
                             f"{PUBLIC_RUNS.name})")
    bike = str(meta["bicycle"]).lower()
    if bike not in BICYCLES:
        raise MocapFileError(f"run {run_id}: bicycle {bike!r} not one of {sorted(BICYCLES)}")
    rider = int(meta.get("rider", rider_from_id))
    return Run(run_id=run_id, rider=rider, trial=trial, bicycle=bike, task=str(meta["task"]),
               condition=str(meta.get("condition", meta["task"])), speed_kmh=speed,
               gear=str(meta.get("gear", "unknown")), t_s=t, markers_m=xyz, raw_m=xyz.copy(),
               source=files["x"], notes=notes)


def write_mat(run: Run, path: str | Path) -> Path:
    """Write a run in the published ``RNNN.mat`` layout (``t, x, y, z, xori, yori, zori, bike,
    condition, V, gearing``; Optotrak frame M, metres), readable by
    :func:`pedalrepro.mocap.reader.read_run`.

    The exports hold raw coordinates only: ``x, y, z`` and ``xori, yori, zori`` are the same.
    """
    import scipy.io

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    m = run.raw_m * M_TO_N  # back to the Optotrak frame
    data = {"t": run.t_s[:, None], "bike": run.bicycle, "condition": run.condition,
            "V": np.array([[run.speed_kmh]]), "gearing": run.gear}
    for i, c in enumerate("xyz"):
        data[c] = run.markers_m[..., i] * M_TO_N[i]
        data[f"{c}ori"] = m[..., i]
    scipy.io.savemat(str(path), data, do_compression=True, oned_as="column")
    return path
