"""Snakemake script: join the chunks of an NT/NP sweep (chunk 0 carries the six example runs
and the one-speed series of Figs 3.18, 3.19, 3.28, 3.29; nonlinear_time_chunk.py).

Writes results/intermediate/time/<method>_<model>.npz with pedalrepro.timesolution (the keys are
listed there). Integrates nothing: it reads the chunks only.
"""

import sys

import numpy as np

from pedalrepro import response, timesolution

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
method, name = snakemake.wildcards.method, snakemake.wildcards.model
v, w = response.speed_cadence_grid(**snakemake.params.grid)
parts = [dict(np.load(p)) for p in snakemake.input.chunks]
out = timesolution.merge_chunks(parts, v, w, method, name, snakemake.params.harmonics,
                                snakemake.params.sample_rate_hz)
timesolution.write(snakemake.output[0], out)
print(f"{method} {name}: merged {len(parts)} chunks, {int(out['fell'].sum())} fell",
      file=sys.stderr)
