"""Snakemake script: 'Your own bicycle' for the book's example bicycle."""

import sys
from pathlib import Path

from pedalrepro import own_bicycle

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
p = snakemake.params
own_bicycle.run(snakemake.input.data_dir, p.bicycle, p.rider, Path(snakemake.output.summary).parent,
                p.linear,
                png_dir=Path(snakemake.output.png).parent, seat_height_m=p.seat_height_m)
