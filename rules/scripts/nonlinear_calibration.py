"""Snakemake script: calibrate the non-linear models' frames to thesis Appendix B.

calibration.csv: every calibrated value beside its uncalibrated one; calibration_checks.csv:
metric, residuals (closed form and the non-linear model's own linearisation), validity;
calibration.yaml: the record the downstream rules read (pedalrepro.nonlinear.calibration).
"""

import sys

from pedalrepro.nonlinear import calibration_report

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration_report.write_results(snakemake.params.models, snakemake.output.table,
                                 snakemake.output.checks, snakemake.output.record)
