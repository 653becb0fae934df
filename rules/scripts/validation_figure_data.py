"""Snakemake script: model maps and series of Figs 4.2-4.10 and the REAL run's panel
(pedalrepro.figdata.validation), with the measured CF spectra's points of Figs 4.10-4.11."""

import sys

from pedalrepro import figdata

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
figdata.write_validation(snakemake.input.per_run, snakemake.input.series, snakemake.output[0],
                         snakemake.params.linear, int(snakemake.params.examples),
                         snakemake.input.source, snakemake.input.spectra)
