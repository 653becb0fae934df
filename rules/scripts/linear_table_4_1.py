"""Snakemake script: Table 4.1 model columns from the particular solution (Sec 4.1, Eq 3.14-3.15).

Runs (system, speed, cadence) from data/parameters/validation_runs.yaml (Table 4.1 header).
"""

import sys

import numpy as np
import pandas as pd

from pedalrepro import linear, params, response

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
runs = params.read_yaml(snakemake.input.runs)["table_4_1"]
rows = []
for run in runs:
    system = run["system"]
    model = linear.linear_model(system)
    h = response.forcing(system, snakemake.params.harmonics)
    k = int(np.nonzero(h.n == 1)[0][0])
    r, s = response.particular_solution(model, run["speed_kmh"] / 3.6,
                                        run["cadence_rpm"] * np.pi / 30, h)
    rows.append({"system": system, "speed_kmh": run["speed_kmh"],
                 "cadence_rpm": run["cadence_rpm"], "roll_model_rad": abs(r[k]),
                 "steer_model_rad": abs(s[k])})
df = pd.DataFrame(rows)
df.to_csv(snakemake.output[0], index=False, float_format="%.8f")
print(df.to_string(), file=sys.stderr)
