"""Snakemake script: open loop vs closed loop vs measurement (closed_loop_validation.csv), Table
4.2 with its closed-loop counterpart and the steer-stiffness sweep (report rows: rule
closed_loop_report)."""

import json
import sys

import numpy as np
import pandas as pd

from pedalrepro import linear, params, response
from pedalrepro.rider import closed_loop, comparison

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
c = snakemake.params.closed_loop
status = json.loads(open(snakemake.input.status).read())
spectra_table = pd.read_csv(snakemake.input.spectra)
measured = pd.read_csv(snakemake.input.measured)
points = comparison.measured_points(spectra_table if status["available"] else None,
                                    params.published(), measured, real_run=c["real_run"])
val = comparison.validation_table(points, snakemake.params.harmonics)
val.to_csv(snakemake.output.validation, index=False, float_format="%.6g")
t42 = comparison.table_4_2_closed(val)
t42.to_csv(snakemake.output.t42, index=False, float_format="%.6g")
sweeps = []
for v_kmh in c["stiffness_speeds_kmh"]:
    hit = spectra_table[np.isclose(spectra_table.speed_kmh, v_kmh)]
    if hit.empty:
        continue
    r = hit.iloc[0]
    sw = comparison.steer_stiffness_sweep(
        "CF", v_kmh / 3.6, float(r.cadence_rpm),
        np.linspace(0.0, c["stiffness_max_n_m_rad"], c["stiffness_points"]),
        snakemake.params.harmonics)
    sw["speed_kmh"] = v_kmh
    sw["roll_measured_rad"] = float(r.roll_nearest_rad)
    sw["steer_measured_rad"] = float(r.steer_nearest_rad)
    sweeps.append(sw)
stiff = (pd.concat(sweeps, ignore_index=True) if sweeps else pd.DataFrame(
    columns=["system", "speed_m_s", "cadence_rpm", "steer_stiffness_n_m_rad", "roll_rad",
             "steer_rad", "stable", "speed_kmh", "roll_measured_rad", "steer_measured_rad"]))
stiff.to_csv(snakemake.output.stiffness, index=False, float_format="%.6g")
# closed-loop (and open-loop LA) time histories from rest at the CF spectra's example speeds
t = response.time_samples(c["time_duration_s"], c["time_sample_rate_hz"])
h = response.forcing("CF", snakemake.params.harmonics)
series = {"t_s": t}
for v_kmh in c["stiffness_speeds_kmh"]:
    hit = spectra_table[np.isclose(spectra_table.speed_kmh, v_kmh)]
    if hit.empty:
        continue
    v, rpm = v_kmh / 3.6, float(hit.iloc[0].cadence_rpm)
    g, stable, control = comparison.rider_gains("CF", np.array([v]))
    roll, steer = closed_loop.closed_loop_time("CF", v, g[0], rpm * np.pi / 30, h, t, control)
    la = response.analytic_time_solution(linear.linear_model("CF"), np.array([v]),
                                         np.array([rpm * np.pi / 30]), h, t)
    key = f"CF_{v_kmh:g}"
    series.update({f"{key}_closed_roll_rad": roll, f"{key}_closed_steer_rad": steer,
                   f"{key}_open_roll_rad": la.roll_rad[0, 0], f"{key}_open_steer_rad":
                   la.steer_rad[0, 0], f"{key}_cadence_rpm": rpm, f"{key}_stable": stable[0]})
np.savez(snakemake.output.time, **series)
print(val.to_string(), t42.to_string(), sep="\n", file=sys.stderr)
