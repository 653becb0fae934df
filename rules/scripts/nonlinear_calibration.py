"""Snakemake script: calibrate the non-linear models' frames to thesis Appendix B.

calibration.csv: every calibrated value beside its uncalibrated one; calibration_checks.csv:
metric, residuals (closed form and the non-linear model's own linearisation), validity;
calibration.yaml: the record the downstream rules read (pedalrepro.nonlinear.calibration).
"""

import sys

from pedalrepro.nonlinear import calibration

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.write_results(snakemake.params.models, snakemake.output.table,
                          snakemake.output.checks, snakemake.output.record)
