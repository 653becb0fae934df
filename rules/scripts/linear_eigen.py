"""Snakemake script: eigenvalues vs speed, tracked and named, and eigen_summary.csv (Sec 3.2.1)."""

import sys

import numpy as np
import pandas as pd

from pedalrepro import linear, response

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
speeds = response.grid(**snakemake.params.eigen_speeds)
rows = []
for name, path in zip(snakemake.params.models, snakemake.output.sweeps, strict=True):
    model = linear.linear_model(name)
    sweep = linear.eigen_sweep(model, speeds)
    s = linear.summarise(model, speeds)
    onset = linear.oscillatory_onset(model, sweep)
    ranges = linear.stable_ranges(model, speeds)
    np.savez(path, speed_m_s=speeds, eigenvalues=sweep.eigenvalues, names=np.array(sweep.names),
             weave_frequency_rad_s=sweep.weave_frequency_rad_s(),
             stable_ranges_m_s=np.array(ranges).reshape(-1, 2),
             weave_speed_m_s=np.nan if s.weave_speed_m_s is None else s.weave_speed_m_s,
             oscillatory_onset_m_s=np.nan if onset is None else onset)
    rows.append({"model": name, "weave_speed_m_s": s.weave_speed_m_s,
                 "capsize_speed_m_s": s.capsize_speed_m_s, "stable_from_m_s": s.stable_from_m_s,
                 "stable_to_m_s": s.stable_to_m_s,
                 "weave_frequency_at_weave_speed_rad_s": s.weave_frequency_at_weave_speed_rad_s,
                 "weave_oscillatory_from_m_s": onset, "note": s.note})
    print(rows[-1], file=sys.stderr)
pd.DataFrame(rows).to_csv(snakemake.output.table, index=False, float_format="%.6f")
