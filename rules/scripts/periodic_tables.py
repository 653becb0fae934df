"""Snakemake script: the tables of the periodic orbits (pedalrepro.periodic)."""

import sys

from pedalrepro import periodic
from pedalrepro.nonlinear import calibration

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.use_file(snakemake.input.calibration)  # frames calibrated to Appendix B
periodic.write_tables(snakemake.input.maps, snakemake.input.branches, snakemake.input.time,
                      snakemake.output.maps, snakemake.output.crossings,
                      snakemake.output.simulation)
