"""Snakemake script: Tables 4.1 and 4.2, the per-run comparison and the real run's comparison
with Table 4.1 by both amplitude methods (Sec 4.2). This rule computes data only: the tables'
report rows are written by the rule validation_report (validation_report.py)."""

import sys

from pedalrepro import validation

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
out, _ = validation.chapter_4_from_files(snakemake.input.measured, snakemake.input.runs,
                                         snakemake.input.source, snakemake.input.model)
for key in ("t41", "t42", "per_run", "comparison"):
    out[key].to_csv(snakemake.output[key], index=False, float_format="%.6g")
print(out["t41"].to_string(), out["t42"].to_string(), out["comparison"].to_string(), sep="\n",
      file=sys.stderr)
