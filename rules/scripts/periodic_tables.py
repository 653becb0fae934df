"""Snakemake script: the tables of the periodic orbits (pedalrepro.periodic)."""

import sys

from pedalrepro import periodic

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
periodic.write_tables(snakemake.input.maps, snakemake.input.branches, snakemake.input.time,
                      snakemake.output.maps, snakemake.output.crossings,
                      snakemake.output.simulation)
