"""Snakemake script: join the report parts into results/tables/reproduction_report.csv; the first
line of its log (and of Snakemake's output) gives the five status counts."""

import sys

from pedalrepro import report

log = open(snakemake.log[0], "w")  # noqa: SIM115
sys.stderr = log
df = report.combine(snakemake.input.parts, snakemake.output[0])
counts = report.summary(df)
line = (f"reproduction report: {len(df)} rows: "
        + ", ".join(f"{n} {s}" for s, n in counts.items()))
print(line, file=log)
print(line)
