"""Snakemake script: roll, steer, yaw, cadence and cadence amplitudes of every run (Sec 4.1).

Writes one row per dynamic run (runs.csv) and the angle series (series.npz, for Figs 4.2-4.9).
"""

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from pedalrepro.mocap import runs

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
source = json.loads(open(snakemake.input.source).read())
index = runs.index_runs(snakemake.input.runs)
rider = int(runs.validation_runs()["rider"])  # the thesis's rider (rider 1's data is corrupt)
index = index[(index.system != "") & (index.speed_kmh > 0) & (index.rider == rider)]
rows, series, failed = [], {}, []
for _, meta in index.iterrows():
    rid = int(meta.run_id)
    try:
        a = runs.analyse_run(meta.file, lowpass_hz=snakemake.params.lowpass_hz or None)
    except (ValueError, OSError) as exc:  # a damaged run is reported, the others go on
        failed.append(rid)
        print(f"RUN {rid} NOT USED: {exc}", file=sys.stderr)
        continue
    rows.append({
        "run_id": rid, "rider": int(meta.rider), "system": meta.system,
        "bicycle": a.run.bicycle, "task": a.run.task, "speed_kmh": a.run.speed_kmh,
        "cadence_rpm": a.cadence.cadence_rpm, "cadence_bin_rpm": a.cadence.cadence_bin_rpm,
        "cadence_crank_rpm": a.cadence.cadence_crank_rpm,
        "roll_measured_rad": a.amplitudes["roll_amp_rad"],
        "steer_measured_rad": a.amplitudes["steer_amp_rad"],
        "yaw_measured_rad": a.amplitudes["yaw_amp_rad"],
        "repaired_fraction": a.kin.repaired_fraction, "data_source": source["data_source"],
    })
    truth = Path(snakemake.input.runs) / "truth" / f"{rid:04d}.npz"
    if source["data_source"] == "synthetic" and truth.is_file():
        # the stand-in's ground truth: how well the extraction recovers it
        tr = np.load(truth)
        for q in ("roll", "steer", "yaw"):
            rows[-1][f"{q}_truth_rms_rad"] = float(
                np.sqrt(np.mean((getattr(a.kin, f"{q}_rad") - tr[f"{q}_rad"]) ** 2)))
        rows[-1]["cadence_truth_error_percent"] = float(
            100 * (a.cadence.cadence_rpm / float(tr["cadence_rpm"]) - 1))
    for name in ("t_s", "roll_rad", "steer_rad", "yaw_rad", "crank_rad"):
        series[f"{rid}_{name}"] = getattr(a.kin, name)
    print(rid, meta.system, a.run.speed_kmh, f"{a.cadence.cadence_rpm:.2f} rpm",
          *a.kin.notes, file=sys.stderr)
if failed:
    print(f"{len(failed)} runs not used (see above): {failed}", file=sys.stderr)
df = pd.DataFrame(rows)
if df.empty:
    raise ValueError("no run of the systems HS, CF, HR, CR found")
df.to_csv(snakemake.output.table, index=False, float_format="%.8g")
np.savez_compressed(snakemake.output.series, **series)
