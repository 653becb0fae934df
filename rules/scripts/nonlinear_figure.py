"""Snakemake script: fig_3_34 (RD PS vs NP) and the Appendix B linearisation comparison."""

import sys

import numpy as np
import pandas as pd

from pedalrepro import figures
from pedalrepro.figures import nonlinear

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
maps = dict(np.load(snakemake.input.maps))
with figures.style():
    figures.save(nonlinear.fig_3_34(maps), snakemake.output.fig_3_34)
    figures.save(nonlinear.fig_linearisation_vs_appendix_b(pd.read_csv(snakemake.input.appendix_b)),
                 snakemake.output.appendix_b)
