"""The run index and the selection of the runs behind Tables 4.1 and 4.2 (Sec 4.1).

Runs are selected by their metadata (rider, bicycle, task, belt speed), never by trial number
alone, so the same code serves the published files and the synthetic stand-in. Systems
(Sec 4.1, Fig 4.1): HS = Stratos, normal pedalling; CF = Browser, normal pedalling;
HR = Stratos, no-hands; CR = Browser, no-hands (``data/parameters/validation_runs.yaml``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from .. import params, paths
from . import cadence as cadence_mod
from . import kinematics
from .reader import Run, parse_run_id, read_metadata, read_run

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


@dataclass
class RunAnalysis:
    """A run with its kinematics, cadence and cadence-frequency amplitudes."""

    run: Run
    kin: kinematics.Kinematics
    cadence: cadence_mod.Cadence
    amplitudes: dict[str, float]


def analyse_run(path: str | Path, lowpass_hz: float | None = kinematics.LOWPASS_HZ
                ) -> RunAnalysis:
    """Read a run file, extract its angles and cadence and the amplitudes at the cadence."""
    run = read_run(path)
    if run.is_static:
        raise ValueError(f"{path}: run {run.run_id} is a static run (no motion to analyse)")
    kin = kinematics.extract(run, lowpass_hz=lowpass_hz)
    cad = cadence_mod.detect_cadence(run, kin)
    amps = cadence_mod.amplitudes_at_cadence(kin, cad, run.sample_rate_hz)
    return RunAnalysis(run, kin, cad, amps)
