"""Snakemake script: draw a group of linear-part figures (pedalrepro.figures.linear.draw).

One job per group keeps the Python and matplotlib start-up cost out of every figure.
"""

import sys
from pathlib import Path

from pedalrepro import figures
from pedalrepro.figures import linear as linear_figures

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
for png in snakemake.output.png:
    fid = Path(png).stem
    with figures.style():
        fig = linear_figures.draw(fid, snakemake.params.linear, snakemake.params.time_methods)
        figures.save(fig, png)
    print(f"{fid}: {png}", file=sys.stderr)
