"""Snakemake script: draw one Section 2 figure from the hybrid-bicycle disturbance arrays."""

import sys

import numpy as np

from pedalrepro import figures
from pedalrepro.figures import section2

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
fid = snakemake.wildcards.fid
with np.load(snakemake.input.npz) as npz:
    data = dict(npz)
with figures.style():
    fig = getattr(section2, fid)(data)
figures.save(fig, snakemake.output.png)
print(f"{fid} -> {snakemake.output.png}", file=sys.stderr)
