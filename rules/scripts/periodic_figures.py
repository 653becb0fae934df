"""Snakemake script: the figures of the periodic orbits (pedalrepro.figures.periodic)."""

import sys

from pedalrepro.figures import periodic

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
periodic.draw_all(snakemake.input, snakemake.output, snakemake.params.models,
                  snakemake.params.methods)
