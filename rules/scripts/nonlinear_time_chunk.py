"""Snakemake script: one chunk (a slice of the speeds) of the NT or NP sweep of one model.

Chunk 0 also integrates the six example runs and the one-speed series (Figs 3.18, 3.19, 3.28,
3.29), so that the join (nonlinear_time.py) integrates nothing and needs no job of its own
start-up cost beyond reading the chunks. The chunk holds ``speed_index`` and the grid arrays of
pedalrepro.timesolution.CHUNK_GRID_KEYS (the join is pedalrepro.timesolution.merge_chunks).
"""

import sys
import time

import numpy as np

from pedalrepro import evaluation, response
from pedalrepro.nonlinear import calibration, sweep

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.use_file(snakemake.input.calibration)  # frames calibrated to Appendix B
method, name = snakemake.wildcards.method, snakemake.wildcards.model
chunk, n_chunks = int(snakemake.wildcards.chunk), int(snakemake.params.chunks)
v, w = response.speed_cadence_grid(**snakemake.params.grid)
idx = np.array_split(np.arange(v.size), n_chunks)[chunk]
settings = sweep.RunSettings(**snakemake.params.settings)
h = response.forcing(name, snakemake.params.harmonics)
start = time.perf_counter()
out = sweep.grid_runs(method, name, v[idx], w, h, settings)
elapsed = time.perf_counter() - start
examples = {}
if chunk == 0:
    pts = evaluation.example_points(name)
    t = response.time_samples(settings.duration_s, settings.sample_rate_hz)
    ex = sweep.time_histories(method, name, pts.speed_m_s, pts.omega_rad_s, h, settings, t)
    series_v = np.full(len(pts.series_omega_rad_s), pts.series_speed_m_s)
    se = sweep.time_histories(method, name, series_v, pts.series_omega_rad_s, h, settings, t)
    examples = dict(example_speed_m_s=pts.speed_m_s, example_omega_rad_s=pts.omega_rad_s,
                    example_t_s=t, series_speed_m_s=series_v,
                    series_omega_rad_s=pts.series_omega_rad_s,
                    **{f"example_{k}": a for k, a in ex.items()},
                    **{f"series_{k}": a for k, a in se.items()})
np.savez_compressed(snakemake.output[0], speed_index=idx, speed_m_s=v[idx], omega_rad_s=w,
                    **out, **examples)
print(f"{method} {name} chunk {chunk}/{n_chunks}: {idx.size * w.size} runs in {elapsed:.1f} s, "
      f"{int(out['fell'].sum())} fell, {int(out['n_rhs'].sum())} rhs calls"
      + (f"; example runs and series in {time.perf_counter() - start - elapsed:.1f} s"
         if examples else ""), file=sys.stderr)
