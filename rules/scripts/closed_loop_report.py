"""Snakemake script: the closed loop's reproduction-report rows (Table 4.2's CF column from the
measured spectra, the benchmark gains at 5.0 m/s), from the tables rule closed_loop_validation and
closed_loop_gains wrote."""

import json
import sys

import numpy as np
import pandas as pd

from pedalrepro import report
from pedalrepro.rider import report_rows

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
status = json.loads(open(snakemake.input.status).read())
t42 = pd.read_csv(snakemake.input.t42)
gains = pd.read_csv(snakemake.input.gains)
bench = gains[(gains.model == "benchmark") & np.isclose(gains.speed_m_s, 5.0)
              & gains.source.str.startswith("rules")]
rows = report_rows.report_rows(t42, bench[["kDelta", "kPhiDot", "kPhi", "kPsi", "kY"]]
                               .to_numpy()[0], status.get("reason", ""))
print(report.write_rows(rows, snakemake.output[0]).to_string(), file=sys.stderr)
