"""The pipeline's treadmill run files: real where they can be had, stand-in otherwise, labelled.

``data_source`` (config) and what each row of the chapter-4 tables is built from
(``data_source`` column of every table, :func:`prepare_runs`):

- ``figshare``: rider 3's published run files (``RNNN.mat``) from the DOI, or one clear error.
  Rows: ``figshare``.
- ``synthetic``: the seeded stand-in only (:mod:`pedalrepro.mocap.synthetic`). Rows:
  ``synthetic``.
- ``auto`` (default; never fails): the figshare files when they can all be had; otherwise the
  stand-in **plus** every real run of the public subset that can be had (cached in the data
  folder or downloadable, :func:`pedalrepro.mocap.fetch.public_files`) and analysed. Rows:
  ``figshare``, or ``synthetic`` and ``public_subset`` (run 3045: real, beside the synthetic
  rows, never pooled into their medians). A public run that cannot be used (3101: no x file)
  is listed with its reason in ``source.json`` (``excluded``).

The run files go to ``<out>/`` (the main source) and ``<out>/public/`` (the public subset,
converted to the published ``.mat`` layout with :func:`pedalrepro.mocap.exports.write_mat`).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pandas as pd

from . import exports, fetch, synthetic

__all__ = ["PUBLIC", "PUBLIC_DIR", "prepare_runs", "series_id", "extract_runs"]

#: ``data_source`` value of the rows built from the real public subset.
PUBLIC = "public_subset"
PUBLIC_DIR = "public"


def _public_runs(out: Path, progressbar: bool, events: list[str]
                 ) -> tuple[dict[int, dict], list[dict]]:
    files = fetch.public_files(progressbar=progressbar, events=events)
    by_run: dict[int, list[Path]] = {}
    for name, path in files.items():
        rid, _ = exports.export_parts(name)
        by_run.setdefault(rid, []).append(Path(path))
    done, excluded = {}, []
    for rid, paths_ in sorted(by_run.items()):
        try:
            run = exports.read_export_run(paths_)
        except (ValueError, OSError) as exc:  # incomplete, unreadable: listed, never fatal
            excluded.append({"run_id": rid, "data_source": PUBLIC, "stage": "read",
                             "reason": str(exc)})
            continue
        exports.write_mat(run, out / PUBLIC_DIR / f"{rid:04d}.mat")
        done[rid] = {"files": sorted(p.name for p in paths_), "speed_kmh": run.speed_kmh,
                     "bicycle": run.bicycle, "task": run.task}
    return done, excluded


def prepare_runs(requested: str, out: str | Path, mocap_cfg: dict, seed: int,
                 progressbar: bool = False) -> dict:
    """Write the run files for the pipeline into ``out`` and return the source record.

    Returns
    -------
    dict
        ``data_source`` (main source: ``figshare`` or ``synthetic``), ``reason``,
        ``public_subset`` (run id -> files and metadata of the real runs in ``out/public``),
        ``excluded`` (runs that could not be used, with the reason), ``events`` (hash
        mismatches, resumed downloads, fallbacks).

    Raises
    ------
    DataUnavailableError
        Only for ``requested == "figshare"`` when the figshare files cannot be had.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    events: list[str] = []
    source, reason = fetch.resolve_source(requested)
    if source == "figshare":
        try:
            files = fetch.run_files(progressbar=progressbar, events=events)
        except (fetch.DataUnavailableError, fetch.HashMismatchError) as exc:
            if requested == "figshare":
                if isinstance(exc, fetch.HashMismatchError):  # names the file and both hashes
                    raise
                raise fetch.DataUnavailableError(fetch.offline_message(exc)) from exc
            source = "synthetic"
            reason = (f"the figshare files could not all be had ({type(exc).__name__}: {exc}); "
                      "the synthetic stand-in is not the measurement")
            events.append(reason)
        else:
            for run_id, path in sorted(files.items()):
                link = out / f"{run_id:04d}.mat"
                if not link.exists():
                    link.symlink_to(Path(path).resolve())
    if source == "synthetic":
        for p in out.glob("*.mat"):
            p.unlink()
        synthetic.write_stand_in(out, mocap_cfg, seed)
    public, excluded = {}, []
    if requested == "auto" and source == "synthetic":
        if (out / PUBLIC_DIR).exists():
            shutil.rmtree(out / PUBLIC_DIR)
        public, excluded = _public_runs(out, progressbar, events)
        if not public:
            events.append("no run of the public subset available (put its files in "
                          f"${fetch.ENV}, see data/registry_public.txt): synthetic rows only")
    return {"data_source": source, "reason": reason, "requested": requested,
            "public_subset": {str(k): v for k, v in public.items()}, "excluded": excluded,
            "events": events}


def series_id(run_id: int, data_source: str) -> str:
    """Key prefix of a run's angle series in ``series.npz`` (public runs apart from the
    stand-in's, which may use the same run numbers)."""
    return f"public_{run_id}" if data_source == PUBLIC else str(int(run_id))


def extract_runs(runs_dir: str | Path, source: dict, lowpass_hz: float | None,
                 log=None) -> tuple[pd.DataFrame, dict[str, np.ndarray], pd.DataFrame]:
    """Analyse rider 3's runs of the four systems in ``runs_dir`` (and ``runs_dir/public``).

    Returns the per-run table (one row per analysed run, ``data_source`` per row, ``analysis``
    = ``full`` or ``partial <start>-<end> s``), the angle series (``<series_id>_<name>``) and
    the runs not used with the criterion that refused them (:func:`runs.analyse_run`: the
    same criteria as ``pedalrepro mocap extract``).
    """
    from . import runs

    def say(*args) -> None:
        if log is not None:
            print(*args, file=log)

    runs_dir = Path(runs_dir)
    rider = int(runs.validation_runs()["rider"])  # the thesis's rider (rider 1's data is corrupt)
    folders = [(runs_dir, source["data_source"])]
    if (runs_dir / PUBLIC_DIR).is_dir() and any((runs_dir / PUBLIC_DIR).glob("*.mat")):
        folders.append((runs_dir / PUBLIC_DIR, PUBLIC))
    rows, series = [], {}
    excluded = [dict(e) for e in source.get("excluded", [])]
    for folder, label in folders:
        index = runs.index_runs(folder)
        index = index[(index.system != "") & (index.speed_kmh > 0) & (index.rider == rider)]
        for _, meta in index.iterrows():
            rid = int(meta.run_id)
            try:
                a = runs.analyse_run(meta.file, lowpass_hz=lowpass_hz or None)
            except (ValueError, OSError) as exc:  # refused or damaged: reported, others go on
                excluded.append({"run_id": rid, "data_source": label, "stage": "extract",
                                 "reason": str(exc)})
                say(f"RUN {rid} ({label}) NOT USED: {exc}")
                continue
            row = {
                "run_id": rid, "rider": int(meta.rider), "system": meta.system,
                "bicycle": a.run.bicycle, "task": a.run.task, "speed_kmh": a.run.speed_kmh,
                "cadence_rpm": a.cadence.cadence_rpm,
                "cadence_bin_rpm": a.cadence.cadence_bin_rpm,
                "cadence_crank_rpm": a.cadence.cadence_crank_rpm,
                "roll_measured_rad": a.amplitudes["roll_amp_rad"],
                "steer_measured_rad": a.amplitudes["steer_amp_rad"],
                "yaw_measured_rad": a.amplitudes["yaw_amp_rad"],
                "roll_bin_rad": a.amplitudes_bin["roll_amp_rad"],
                "steer_bin_rad": a.amplitudes_bin["steer_amp_rad"],
                "repaired_fraction": a.kin.repaired_fraction, "analysis": a.status,
                "duration_s": a.segment_s[1] - a.segment_s[0], "data_source": label,
                "series_id": series_id(rid, label),
            }
            truth = folder / "truth" / f"{rid:04d}.npz"
            if label == "synthetic" and truth.is_file() and not a.partial:
                # the stand-in's ground truth: how well the extraction recovers it
                tr = np.load(truth)
                for q in ("roll", "steer", "yaw"):
                    row[f"{q}_truth_rms_rad"] = float(
                        np.sqrt(np.mean((getattr(a.kin, f"{q}_rad") - tr[f"{q}_rad"]) ** 2)))
                row["cadence_truth_error_percent"] = float(
                    100 * (a.cadence.cadence_rpm / float(tr["cadence_rpm"]) - 1))
            rows.append(row)
            for name in ("t_s", "roll_rad", "steer_rad", "yaw_rad", "crank_rad"):
                series[f"{row['series_id']}_{name}"] = getattr(a.kin, name)
            say(rid, label, meta.system, a.run.speed_kmh, f"{a.cadence.cadence_rpm:.2f} rpm",
                a.status, *a.notes, *a.kin.notes)
    df = pd.DataFrame(rows)
    if df.empty or not (df.data_source == source["data_source"]).any():
        raise ValueError(f"no run of the systems HS, CF, HR, CR found in {runs_dir}")
    return df, series, pd.DataFrame(excluded, columns=["run_id", "data_source", "stage",
                                                       "reason"])
