"""Snakemake script: Tables 4.1 and 4.2, the per-run comparison and the report part (Sec 4.2)."""

import json
import sys

import pandas as pd

from pedalrepro import params, report, validation
from pedalrepro.mocap import runs

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
source = json.loads(open(snakemake.input.source).read())
ds = source["data_source"]
measured = pd.read_csv(snakemake.input.measured)
index = runs.index_runs(snakemake.input.runs)
cadences = dict(zip(measured.run_id, measured.cadence_rpm, strict=True))
selection = runs.table_4_1_runs(index, cadences)
model = pd.read_csv(snakemake.input.model)
t41 = validation.table_4_1(measured, selection, model, ds)
per_run = validation.per_run_table(measured, ds)
t42 = validation.table_4_2(per_run, ds)
t41.to_csv(snakemake.output.t41, index=False, float_format="%.6g")
t42.to_csv(snakemake.output.t42, index=False, float_format="%.6g")
per_run.to_csv(snakemake.output.per_run, index=False, float_format="%.6g")
rows = validation.report_rows(t41, t42, params.published(), ds,
                              "" if ds == "figshare" else source["reason"])
report.write_rows(rows, snakemake.output.report)
print(t41.to_string(), t42.to_string(), sep="\n", file=sys.stderr)
