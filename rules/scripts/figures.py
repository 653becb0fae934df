"""Snakemake script: draw the figures of one registry group (pedalrepro.figures.registry)."""

import sys
from pathlib import Path

from pedalrepro.figures import registry

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
pngs = [Path(p) for p in snakemake.output.png]
registry.write([p.stem for p in pngs], pngs[0].parents[1])
