"""Snakemake script: join the report parts into results/tables/reproduction_report.csv."""

import sys

from pedalrepro import report

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
df = report.combine(snakemake.input.parts, snakemake.output[0])
print(f"{len(df)} rows: {report.summary(df)}", file=sys.stderr)
