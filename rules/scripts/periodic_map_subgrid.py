"""Snakemake script: the thesis-grid orbit map cut out of the finer grid's (pedalrepro.periodic)."""

import sys

from pedalrepro import periodic

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
out = periodic.write_submap(snakemake.output[0], snakemake.input.fine, **snakemake.params.grid)
print(periodic.map_summary([out]).T, file=sys.stderr)
