"""Snakemake script: Tables 4.1 and 4.2, the per-run comparison, the real run's comparison with
Table 4.1 (both amplitude methods) and the report part (Sec 4.2)."""

import json
import sys

import pandas as pd

from pedalrepro import params, report, validation
from pedalrepro.mocap import runs

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
source = json.loads(open(snakemake.input.source).read())
measured = pd.read_csv(snakemake.input.measured)
main = measured[measured.data_source == source["data_source"]]
selection = runs.table_4_1_runs(runs.index_runs(snakemake.input.runs),
                                dict(zip(main.run_id, main.cadence_rpm, strict=True)))
out = validation.chapter_4_tables(measured, selection, pd.read_csv(snakemake.input.model),
                                  source, params.published())
for key in ("t41", "t42", "per_run", "comparison"):
    out[key].to_csv(snakemake.output[key], index=False, float_format="%.6g")
report.write_rows(out["report"], snakemake.output.report)
print(out["t41"].to_string(), out["t42"].to_string(), out["comparison"].to_string(), sep="\n",
      file=sys.stderr)
