"""Snakemake script: continuation in speed of one model's periodic orbits (pedalrepro.periodic)."""

import sys

from pedalrepro import periodic
from pedalrepro.nonlinear import calibration

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.use_file(snakemake.input.calibration)  # frames calibrated to Appendix B
p = snakemake.params
branches = periodic.write_branches(snakemake.output[0], snakemake.wildcards.model, p.methods,
                                   p.cadence_rpm, p.speed_range_m_s, p.torque_scales, ds=p.ds,
                                   rtol=p.rtol, max_growth=p.max_growth)
for b in branches:
    print(b.method, len(b.values), "points, crossings:", b.crossings, file=sys.stderr)
