"""Snakemake script: one chunk (a slice of the speeds) of the NT or NP sweep of one model."""

import sys
import time

import numpy as np

from pedalrepro import response
from pedalrepro.nonlinear import sweep

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
method, name = snakemake.wildcards.method, snakemake.wildcards.model
chunk, n_chunks = int(snakemake.wildcards.chunk), int(snakemake.params.chunks)
v, w = response.speed_cadence_grid(**snakemake.params.grid)
idx = np.array_split(np.arange(v.size), n_chunks)[chunk]
settings = sweep.RunSettings(**snakemake.params.settings)
h = response.forcing(name, snakemake.params.harmonics)
start = time.perf_counter()
out = sweep.grid_runs(method, name, v[idx], w, h, settings)
elapsed = time.perf_counter() - start
np.savez_compressed(snakemake.output[0], speed_index=idx, speed_m_s=v[idx], omega_rad_s=w, **out)
print(f"{method} {name} chunk {chunk}/{n_chunks}: {idx.size * w.size} runs in {elapsed:.1f} s, "
      f"{int(out['fell'].sum())} fell, {int(out['n_rhs'].sum())} rhs calls", file=sys.stderr)
