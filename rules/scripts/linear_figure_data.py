"""Snakemake script: arrays the linear figures draw (pedalrepro.figdata.write_linear)."""

import sys

from pedalrepro import figdata

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
figdata.write_linear(dict(snakemake.output.items()), snakemake.params.linear)
