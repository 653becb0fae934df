"""Snakemake script: the hands-free lean-torque rider on Moore's leaning-rider plant against
speed (pedalrepro.rider.lean), on the closed-loop maps' speed grid."""

import sys

import numpy as np

from pedalrepro.rider import lean

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
c = snakemake.params.closed_loop
speeds = np.round(np.arange(c["map_speed_min_m_s"], c["speed_max_m_s"] + 1e-9,
                            c["map_speed_step_m_s"]), 9)
t = lean.lean_rider_table(speeds)
t.to_csv(snakemake.output.table, index=False, float_format="%.6g")
print(f"lean rider: {len(t)} speeds {speeds[0]}-{speeds[-1]} m/s; closed loop stable at "
      f"{int(t.closed_loop_stable.sum())}; rule kDelta "
      f"{t.rule_kDelta_n_m_rad.min():.4g} to {t.rule_kDelta_n_m_rad.max():.4g} N m/rad",
      file=sys.stderr)
