"""Snakemake script: roll, steer, yaw, cadence and cadence amplitudes of every run (Sec 4.1).

Writes one row per analysed run (measured.csv, data_source per row), the angle series
(series.npz, for Figs 4.2-4.9) and the runs not used with the reason (excluded.csv).
"""

import json
import sys

import numpy as np

from pedalrepro.mocap import prepare

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
measured, series, excluded = prepare.extract_runs(
    snakemake.input.runs, json.loads(open(snakemake.input.source).read()),
    snakemake.params.lowpass_hz, log=sys.stderr)
measured.to_csv(snakemake.output.table, index=False, float_format="%.8g")
excluded.to_csv(snakemake.output.excluded, index=False)
np.savez_compressed(snakemake.output.series, **series)
