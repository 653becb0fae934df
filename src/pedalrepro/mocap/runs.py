"""The run index and the selection of the runs behind Tables 4.1 and 4.2 (Sec 4.1).

Runs are selected by their metadata (rider, bicycle, task, belt speed), never by trial number
alone, so the same code serves the published files and the synthetic stand-in. Systems
(Sec 4.1, Fig 4.1): HS = Stratos, normal pedalling; CF = Browser, normal pedalling;
HR = Stratos, no-hands; CR = Browser, no-hands (``data/parameters/validation_runs.yaml``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pandas as pd

from .. import params, paths
from . import cadence as cadence_mod
from . import kinematics
from .reader import Run, parse_run_id, read_metadata, read_run

__all__ = [
    "SYSTEM_OF", "validation_runs", "index_runs", "run_path", "select_system", "table_4_1_runs",
    "MAX_GAP_S", "MAX_INTERPOLATED_SHARE", "MIN_SEGMENT_S", "MIN_FOOT_AMPLITUDE_M",
    "MAX_CADENCE_DISAGREEMENT", "RunRefusedError", "RunAnalysis", "load_run", "gaps",
    "usable_segment", "excerpt", "check_lowpass", "check_length", "analyse_run", "analyse_loaded",
]

SYSTEM_OF: dict[tuple[str, str], str] = {
    ("stratos", "pedalling"): "HS", ("browser", "pedalling"): "CF",
    ("stratos", "nohands"): "HR", ("browser", "nohands"): "CR",
}


def validation_runs() -> dict:
    """``data/parameters/validation_runs.yaml``: Table 4.1 conditions and rider 3's runs."""
    return params.read_yaml(paths.PARAMETERS / "validation_runs.yaml")


def index_runs(files: dict[int, Path] | list[Path] | str | Path) -> pd.DataFrame:
    """Metadata of run files (a folder, a list of paths, or run id -> path), with ``system``.

    Static runs and runs of other tasks get an empty ``system``.
    """
    if isinstance(files, (str, Path)):
        files = sorted(Path(files).glob("[0-9][0-9][0-9][0-9].mat"))
    paths_ = list(files.values()) if isinstance(files, dict) else list(files)
    rows = [read_metadata(p) for p in paths_]
    df = pd.DataFrame(rows)
    if df.empty:
        raise ValueError("no run files RNNN.mat to index")
    df["system"] = [SYSTEM_OF.get((b, t), "") for b, t in zip(df.bicycle, df.task, strict=True)]
    return df.sort_values("run_id").reset_index(drop=True)


def run_path(index: pd.DataFrame, run_id: int) -> Path:
    """File of a run in the index; a clear error for an unknown run number."""
    parse_run_id(int(run_id))  # rider 1-3, trial 1-110
    hit = index.loc[index.run_id == int(run_id), "file"]
    if hit.empty:
        raise KeyError(f"unknown run {run_id}: not in this data set ({len(index)} runs, "
                       f"{index.run_id.min()}-{index.run_id.max()})")
    return Path(hit.iloc[0])


def select_system(index: pd.DataFrame, system: str, rider: int | None = None) -> pd.DataFrame:
    """All runs of a system (Table 4.2), of rider 3 by default, sorted by speed."""
    if system not in params.MODELS:
        raise KeyError(f"unknown system {system!r}: expected one of {params.MODELS}")
    rider = int(validation_runs()["rider"]) if rider is None else rider
    sel = index[(index.system == system) & (index.rider == rider) & (index.speed_kmh > 0)]
    return sel.sort_values(["speed_kmh", "run_id"]).reset_index(drop=True)


def table_4_1_runs(index: pd.DataFrame, cadence_rpm: dict[int, float] | None = None
                   ) -> pd.DataFrame:
    """The run of each Table 4.1 condition: same system, belt speed within the tolerance.

    Columns ``system, speed_kmh, cadence_rpm`` (the table header) and ``run_id``. When several
    runs match (the data set has repeated speeds and runs in another gear), the one whose
    detected cadence (``cadence_rpm``: run id -> rpm, when given) is closest to the header's is
    used, then the closest speed, then the lowest run number.
    """
    v = validation_runs()
    tol = float(v["speed_match_tolerance_kmh"])
    rows = []
    for cond in v["table_4_1"]:
        sel = select_system(index, cond["system"]).copy()
        sel["dv"] = np.abs(sel.speed_kmh - float(cond["speed_kmh"]))
        sel = sel[sel.dv <= tol]
        if sel.empty:
            avail = sorted(select_system(index, cond["system"]).speed_kmh.unique())
            raise KeyError(f"no {cond['system']} run at {cond['speed_kmh']} km/h (+-{tol}) in the "
                           f"data set: available speeds {avail}")
        sel["dc"] = [abs(cadence_rpm[r] - float(cond["cadence_rpm"])) if cadence_rpm and
                     r in cadence_rpm else 0.0 for r in sel.run_id]
        best = sel.sort_values(["dc", "dv", "run_id"]).iloc[0]
        rows.append({"system": cond["system"], "speed_kmh": float(cond["speed_kmh"]),
                     "cadence_rpm": float(cond["cadence_rpm"]), "run_id": int(best.run_id)})
    return pd.DataFrame(rows)


#: Longest stretch (s) over which the angles may be interpolated. A linearly interpolated gap
#: of ``g`` s removes the cadence oscillation there; in the Hann-windowed DFT of a ``T`` s record
#: a gap at the centre weighs at most ``2 g / T`` of the amplitude: 0.5 s in 60 s -> at most
#: 1.7 %, about half the last printed digit of Table 4.1 (0.0005 rad of 0.011-0.031 rad).
MAX_GAP_S = 0.5
#: Largest Hann-weighted share of interpolated samples (many short gaps add up, same bound).
MAX_INTERPOLATED_SHARE = 0.02
#: Shortest analysable record (s): a whole run as well as the stretch analysed when long gaps
#: split a run. MEASURED (``scripts/measure_min_length.py``): every excerpt of run 3045
#: (real, 60 s; starts every 2.5 s) analysed as a run, its cadence amplitudes against the whole
#: record's (roll 0.01184, steer 0.02181 rad): median | largest error of roll, steer
#: 3 s: 21 | 82 %, 15 | 56 %; 10 s: 6.9 | 41 %, 4.0 | 26 %; 15 s: 5.8 | 20 %, 2.4 | 12 %;
#: 20 s: 4.7 | 10 %, 1.3 | 6.8 %; 30 s: 3.1 | 4.5 %, 1.5 | 3.0 %. 20 s is the shortest length
#: whose median error stays below 5 %, the last printed digit of Table 4.1's measured
#: amplitudes (0.0005 rad of 0.011 rad), with at most 10 % for any excerpt; its Hann main lobe
#: (``4 / T`` = 0.2 Hz = 12 rpm) keeps the cadence (60-90 rpm) clear of the weave and control
#: band below 0.5 Hz (Sec 4.2). config/schema.yaml's ``mocap.duration_s`` has the same minimum.
MIN_SEGMENT_S = 20.0
#: Smallest amplitude (m) of the right foot's forward motion at the cadence: while pedalling it
#: is about the crank length (0.17 m, legs.yaml); the marker noise is 0.15 mm. A run below this
#: has no pedalling to analyse (frozen, towed or a swapped foot marker).
MIN_FOOT_AMPLITUDE_M = 0.05
#: Largest relative difference between the foot's spectral peak and the mean crank-angle rate
#: (they agree within 0.1 % on steady pedalling; a run where they differ has no single
#: cadence).
MAX_CADENCE_DISAGREEMENT = 0.02


class RunRefusedError(ValueError):
    """A run that cannot be analysed: the message names the measured criterion that failed."""


@dataclass
class RunAnalysis:
    """A run with its kinematics, cadence and cadence-frequency amplitudes.

    Attributes
    ----------
    amplitudes
        At the exact cadence (Hann DFT evaluated there; the project's method).
    amplitudes_bin
        At the Hann DFT bin nearest the whole-bin cadence (the thesis's method).
    segment_s
        ``(start, end)`` of the analysed stretch (s): the whole run unless long gaps forced a
        partial analysis (``partial`` True, ``notes`` say why).
    """

    run: Run
    kin: kinematics.Kinematics
    cadence: cadence_mod.Cadence
    amplitudes: dict[str, float]
    amplitudes_bin: dict[str, float] = field(default_factory=dict)
    segment_s: tuple[float, float] = (0.0, 0.0)
    partial: bool = False
    notes: list[str] = field(default_factory=list)

    @property
    def status(self) -> str:
        """``"full"`` or ``"partial <start>-<end> s"``."""
        return (f"partial {self.segment_s[0]:.2f}-{self.segment_s[1]:.2f} s" if self.partial
                else "full")


def load_run(source: str | Path | list | dict) -> Run:
    """A run from a ``RNNN.mat`` file or from per-coordinate exports (one file, whose siblings
    are found beside it, or the list of them); any other file gets an error listing what is
    read (:data:`pedalrepro.mocap.reader.FORMATS`)."""
    from . import exports

    if isinstance(source, (list, tuple, dict)):
        return exports.read_export_run(source)
    path = Path(source)
    if exports.is_export(path):
        return exports.read_export_run(path)
    return read_run(path)


def gaps(valid: np.ndarray, t_s: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges ``[i0, i1)`` of the runs of ``False`` in ``valid``."""
    bad = np.concatenate([[False], ~np.asarray(valid, bool), [False]])
    edges = np.flatnonzero(np.diff(bad.astype(int)))
    return list(zip(edges[::2], edges[1::2], strict=True))


def usable_segment(valid: np.ndarray, t_s: np.ndarray, max_gap_s: float = MAX_GAP_S
                   ) -> tuple[int, int, list[tuple[float, float]]]:
    """The longest stretch ``[i0, i1)`` without a gap longer than ``max_gap_s``, and the long
    gaps as ``(start, end)`` times."""
    dt = float(np.median(np.diff(t_s)))
    long_ = [(a, b) for a, b in gaps(valid, t_s) if (b - a) * dt > max_gap_s]
    bounds = [0] + [x for a, b in long_ for x in (a, b)] + [len(t_s)]
    pieces = list(zip(bounds[::2], bounds[1::2], strict=True))
    i0, i1 = max(pieces, key=lambda p: p[1] - p[0])
    return int(i0), int(i1), [(float(t_s[a]), float(t_s[b - 1] + dt)) for a, b in long_]


def excerpt(run: Run, i0: int, i1: int) -> Run:
    """Samples ``[i0, i1)`` of a run (a stretch between gaps, or an excerpt to measure with)."""
    return replace(run, t_s=run.t_s[i0:i1], markers_m=run.markers_m[i0:i1],
                   raw_m=run.raw_m[i0:i1], notes=list(run.notes))


def _check_pedalling(run: Run, kin: kinematics.Kinematics, cad: cadence_mod.Cadence) -> None:
    from .. import spectral

    foot = cadence_mod.foot_signal(run, kin)
    amp = float(spectral.amplitude_at(foot - foot.mean(), run.sample_rate_hz, cad.cadence_hz))
    if amp < MIN_FOOT_AMPLITUDE_M:
        raise RunRefusedError(
            f"run {run.run_id}: no pedalling found: the right-foot marker (1) moves "
            f"{amp * 1e3:.1f} mm at its strongest frequency in the cadence band "
            f"({cad.cadence_rpm:.2f} rpm), below {MIN_FOOT_AMPLITUDE_M * 1e3:.0f} mm (a pedalling "
            "foot moves about one crank length, 170 mm): a frozen or towed run has no cadence; "
            "refused")
    rel = abs(cad.cadence_crank_rpm / cad.cadence_rpm - 1.0)
    if rel > MAX_CADENCE_DISAGREEMENT:
        raise RunRefusedError(
            f"run {run.run_id}: no steady cadence: the foot's spectral peak "
            f"({cad.cadence_rpm:.2f} rpm) and the mean crank-angle rate "
            f"({cad.cadence_crank_rpm:.2f} rpm) differ by {100 * rel:.1f} % (more than "
            f"{100 * MAX_CADENCE_DISAGREEMENT:g} %); refused")


def check_lowpass(lowpass_hz: float | None, sample_rate_hz: float, source: str) -> None:
    """A low-pass cut-off is ``None``/0 (off) or a finite frequency above 0 and below the
    Nyquist rate ``sample_rate_hz / 2``; :class:`RunRefusedError` naming ``source`` otherwise
    (``nan`` used to end in "attempt to get argmin of an empty sequence")."""
    if lowpass_hz is None or lowpass_hz == 0:
        return
    if not (np.isfinite(lowpass_hz) and 0 < lowpass_hz < sample_rate_hz / 2):
        raise RunRefusedError(
            f"{source}: low-pass cut-off {lowpass_hz!r} Hz must be a finite frequency above 0 "
            f"and below the Nyquist rate {sample_rate_hz / 2:g} Hz of this run "
            "(--lowpass-hz, or --no-lowpass)")


def check_length(run: Run) -> float:
    """The record's length (s); :class:`RunRefusedError` when shorter than
    :data:`MIN_SEGMENT_S`, the shortest analysable stretch (a whole record as well as a stretch
    between gaps)."""
    dur = len(run.t_s) / run.sample_rate_hz
    if dur < MIN_SEGMENT_S - 0.5 / run.sample_rate_hz:
        raise RunRefusedError(
            f"run {run.run_id}: record too short: {dur:.2f} s ({len(run.t_s)} samples at "
            f"{run.sample_rate_hz:g} Hz), less than the {MIN_SEGMENT_S:g} s minimum analysable "
            "length (runs.MIN_SEGMENT_S: shorter excerpts of the real run 3045 miss its 60 s "
            "cadence amplitudes by over 5 % typically and up to 82 % at 3 s, "
            "scripts/measure_min_length.py); refused")
    return dur


def analyse_run(path: str | Path | list | dict,
                lowpass_hz: float | None = kinematics.LOWPASS_HZ) -> RunAnalysis:
    """Read a run (``.mat`` or exports), extract its angles, cadence and cadence amplitudes.

    Quality criteria (the same in the CLI and the pipeline): the low-pass cut-off finite and
    below the Nyquist rate, the record at least :data:`MIN_SEGMENT_S` long (else refused as
    too short, whatever else is wrong with it); gaps over which the angles are
    interpolated must be at most :data:`MAX_GAP_S` long and cover at most
    :data:`MAX_INTERPOLATED_SHARE` of the Hann-weighted record; otherwise the longest stretch
    between long gaps is analysed if it lasts :data:`MIN_SEGMENT_S` (``partial``, with a
    note), else the run is refused. The right foot must move at least
    :data:`MIN_FOOT_AMPLITUDE_M` at the cadence and the cadence must agree with the crank-angle
    rate within :data:`MAX_CADENCE_DISAGREEMENT`.

    Raises
    ------
    RunRefusedError
        A criterion above fails (the message names it and the measured value).
    MocapFileError, ValueError
        Unreadable or incomplete files, static runs, too few markers.
    """
    run = load_run(path)
    if run.is_static:
        raise ValueError(f"{path}: run {run.run_id} is a static run (no motion to analyse)")
    return analyse_loaded(run, lowpass_hz)


def analyse_loaded(run: Run, lowpass_hz: float | None = kinematics.LOWPASS_HZ) -> RunAnalysis:
    """:func:`analyse_run` of a run already read (e.g. an excerpt, ``scripts/
    measure_min_length.py``): the record's length (:func:`check_length`) and the low-pass
    cut-off (:func:`check_lowpass`) are checked first."""
    from .. import spectral

    check_lowpass(lowpass_hz, run.sample_rate_hz, f"run {run.run_id}")
    check_length(run)
    kin = kinematics.extract(run, lowpass_hz=lowpass_hz)
    notes: list[str] = []
    i0, i1, long_gaps = usable_segment(kin.valid, run.t_s)
    n = len(run.t_s)
    partial = bool(long_gaps)
    if not long_gaps:
        h = spectral.window(n, "hann")
        share = float(np.sum(h[~kin.valid]) / np.sum(h))
        if share > MAX_INTERPOLATED_SHARE:
            raise RunRefusedError(
                f"run {run.run_id}: {100 * share:.1f} % of the (Hann-weighted) record is "
                f"interpolated across gaps, more than {100 * MAX_INTERPOLATED_SHARE:g} %: the "
                "cadence amplitudes would be too low; refused")
    else:
        dur = float(run.t_s[i1 - 1] - run.t_s[i0]) + 1.0 / run.sample_rate_hz
        listed = ", ".join(f"{a:.2f}-{b:.2f} s ({b - a:.2f} s)" for a, b in long_gaps)
        if dur < MIN_SEGMENT_S - 0.5 / run.sample_rate_hz:
            raise RunRefusedError(
                f"run {run.run_id}: gaps longer than {MAX_GAP_S:g} s ({listed}) leave at most "
                f"{dur:.1f} s without a long gap, less than the {MIN_SEGMENT_S:g} s needed; "
                "interpolating over them would lower the cadence amplitudes; refused")
        notes.append(f"PARTIAL: analysed {run.t_s[i0]:.2f}-{run.t_s[i0] + dur:.2f} s "
                     f"({dur:.1f} of {n / run.sample_rate_hz:.1f} s): gaps longer than "
                     f"{MAX_GAP_S:g} s at {listed} are not interpolated over")
        run = excerpt(run, i0, i1)
        kin = kinematics.extract(run, lowpass_hz=lowpass_hz)
    cad = cadence_mod.detect_cadence(run, kin)
    _check_pedalling(run, kin, cad)
    amps = cadence_mod.amplitudes_at_cadence(kin, cad, run.sample_rate_hz)
    amps_bin = cadence_mod.amplitudes_nearest_bin(kin, cad, run.sample_rate_hz)
    seg = (float(run.t_s[0]), float(run.t_s[-1] + 1.0 / run.sample_rate_hz))
    return RunAnalysis(run, kin, cad, amps, amps_bin, seg, partial, notes)
