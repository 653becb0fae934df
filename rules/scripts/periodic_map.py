"""Snakemake script: periodic orbits of one model and method on one grid (pedalrepro.periodic)."""

import sys

from pedalrepro import periodic
from pedalrepro.nonlinear import calibration

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.use_file(snakemake.input.calibration)  # frames calibrated to Appendix B
out = periodic.write_map(snakemake.output[0], snakemake.wildcards.model,
                         snakemake.wildcards.method, **snakemake.params.grid,
                         rtol=snakemake.params.rtol, max_growth=snakemake.params.max_growth)
print(periodic.map_summary([out | {"model": snakemake.wildcards.model,
                                   "method": snakemake.wildcards.method}]).T, file=sys.stderr)
