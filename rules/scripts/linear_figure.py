"""Snakemake script: draw one linear-part figure by id (pedalrepro.figures.linear.draw)."""

import sys

from pedalrepro import figures
from pedalrepro.figures import linear as linear_figures

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
with figures.style():
    fig = linear_figures.draw(snakemake.wildcards.fid, snakemake.config,
                              snakemake.params.time_methods)
    figures.save(fig, snakemake.output.png)
