"""Snakemake script: the figures of the closed loop (pedalrepro.figures.closed_loop)."""

import sys

from pedalrepro.figures import closed_loop

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
closed_loop.draw_all(snakemake.input, snakemake.output)
