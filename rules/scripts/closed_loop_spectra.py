"""Snakemake script: the measured closed-loop spectra of CF (Moore's MotionCapture figures),
read from the data folder (downloaded when missing and online); the cadence table and the
arrays of the figure. Offline without the files: an empty table and the reason."""

import json
import sys

import numpy as np
import pandas as pd

from pedalrepro.mocap import fetch, spectra

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
events: list[str] = []
try:
    files = spectra.fetch_files(events=events)
    data = spectra.read_all(files)
    table = spectra.cadence_table(data)
    status = {"available": True, "reason": "", "label": spectra.LABEL, "events": events}
    arrays = {f"{coord}_{int(v)}_{k}": getattr(s, k) for coord in ("roll", "steer", "yaw")
              for v, s in data[coord].items() for k in ("frequency_hz", "amplitude_rad")}
except (fetch.DataUnavailableError, fetch.HashMismatchError) as exc:
    table = pd.DataFrame(columns=["system", "speed_kmh", "cadence_hz", "cadence_rpm", "weave_hz",
                                  "frequency_step_hz", "roll_nearest_rad", "roll_peak2_rad",
                                  "steer_nearest_rad", "steer_peak2_rad", "yaw_nearest_rad",
                                  "yaw_peak2_rad", "source"])
    status = {"available": False, "label": spectra.LABEL, "events": events,
              "reason": "the measured spectra (data/registry_spectra.txt) are not in the data "
                        f"folder (${fetch.ENV}) and cannot be downloaded "
                        f"({type(exc).__name__})"}
    print(f"spectra unavailable: {exc}", file=sys.stderr)
    arrays = {}
print(json.dumps(status, indent=1), file=sys.stderr)
table.to_csv(snakemake.output.table, index=False, float_format="%.8g")
np.savez(snakemake.output.arrays, **arrays)
with open(snakemake.output.status, "w") as fh:
    json.dump(status, fh, indent=1)
