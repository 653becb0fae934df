"""Snakemake script: Table D.1 (Fourier amplitudes and phases of the right-leg COM) in long format.

Columns: case (hybrid_O, hybrid_W, city_O, city_W), axis (X, Z), n, amplitude_m, phase_rad, with
x(t) = X0 + sum_n amplitude cos(n omega t + phase) (thesis Appendix D, errata item 9).
"""

import sys

import numpy as np
import pandas as pd

from pedalrepro import legs

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
harmonics = np.arange(1, int(snakemake.params.harmonics) + 1)
rows = []
for case in ("hybrid_O", "hybrid_W", "city_O", "city_W"):
    bicycle, com = case.split("_")
    geometry = legs.leg_geometry(bicycle, com)
    x, z = legs.com_fourier(geometry, harmonics, int(snakemake.params.samples))
    for axis, coef in (("X", x), ("Z", z)):
        for n, c in zip(harmonics, coef, strict=True):
            rows.append({"case": case, "axis": axis, "n": int(n), "amplitude_m": abs(c),
                         "phase_rad": float(np.angle(c))})
    print(f"{case}: {geometry}", file=sys.stderr)
df = pd.DataFrame(rows)
if not np.all(np.isfinite(df[["amplitude_m", "phase_rad"]].to_numpy())):
    raise ValueError("Table D.1 has non-finite entries")
df.to_csv(snakemake.output.table, index=False, float_format="%.15g")
print(f"{len(df)} rows -> {snakemake.output.table}", file=sys.stderr)
