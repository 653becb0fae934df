"""Snakemake script: fig_3_34 (RD PS vs NP), fig_e_1 and the Appendix B linearisation comparison."""

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
    figures.save(nonlinear.fig_e_1(dict(np.load(snakemake.input.eigen_cf)),
                                   dict(np.load(snakemake.input.eigen_e_1))),
                 snakemake.output.fig_e_1)
