"""Snakemake script: one revolution of the pedalling disturbance of one bicycle (Sec 2.1-2.2).

Writes the arrays the Section 2 figures and notebook read (keys: disturbance.to_arrays).
"""

import sys
from pathlib import Path

import numpy as np

from pedalrepro import disturbance

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
bicycle = snakemake.wildcards.bicycle
cadence_rad_s = float(snakemake.params.cadence_rpm) * 2 * np.pi / 60
d = disturbance.pedalling_disturbance(bicycle, "O", cadence_rad_s,
                                      samples_per_revolution=int(snakemake.params.samples))
arrays = disturbance.to_arrays(d)
bad = [k for k, v in arrays.items() if not np.all(np.isfinite(v))]
if bad:
    raise ValueError(f"non-finite arrays for {bicycle}: {bad}")
Path(snakemake.output.npz).parent.mkdir(parents=True, exist_ok=True)
np.savez_compressed(snakemake.output.npz, **arrays)
print(f"{bicycle}: {len(d.t_s)} samples at {cadence_rad_s:.6g} rad/s -> {snakemake.output.npz}",
      file=sys.stderr)
