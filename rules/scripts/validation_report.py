"""Snakemake script: the report rows of chapter 4 (Tables 4.1 and 4.2 and the real run, Sec 4.2)
from the same inputs as validation_tables (recomputed in memory, so the values checked are the
unrounded ones, not the tables' six digits); reads only."""

import sys

from pedalrepro import params, report, validation, validation_report

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
tables, source = validation.chapter_4_from_files(
    snakemake.input.measured, snakemake.input.runs, snakemake.input.source, snakemake.input.model)
rows = validation_report.chapter_4_rows(tables, source, params.published())
report.write_rows(rows, snakemake.output.report)
print(f"{len(rows)} report rows ({source['data_source']})", file=sys.stderr)
