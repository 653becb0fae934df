"""Snakemake script: join the chunks of an NT/NP sweep (chunk 0 carries the six example runs
and the one-speed series of Figs 3.18, 3.19, 3.28, 3.29; nonlinear_time.py).

Writes results/intermediate/time/<method>_<model>.npz in the format of CONTRIBUTING.md.
Integrates nothing: it reads the chunks only.
"""

import sys

import numpy as np

from pedalrepro import response

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
method, name = snakemake.wildcards.method, snakemake.wildcards.model
v, w = response.speed_cadence_grid(**snakemake.params.grid)
parts = [dict(np.load(p)) for p in snakemake.input.chunks]
out = {k: np.concatenate([p[k] for p in parts]) for k in
       ("roll_amp_rad", "steer_amp_rad", "t_end_s", "fell", "n_rhs")}
order = np.concatenate([p["speed_index"] for p in parts])
if not np.array_equal(np.sort(order), np.arange(v.size)):
    raise ValueError(f"chunks of {method}_{name} do not cover the speed grid")
out = {k: a[np.argsort(order)] for k, a in out.items()}
first = [p for p in parts if "example_roll_rad" in p]
if len(first) != 1:
    raise ValueError(f"chunks of {method}_{name}: {len(first)} carry the example runs, "
                     "expected exactly one (chunk 0)")
examples = {k: a for k, a in first[0].items() if k.startswith(("example_", "series_"))}
np.savez_compressed(
    snakemake.output[0], speed_m_s=v, omega_rad_s=w, method=method, model=name,
    harmonics=np.asarray(snakemake.params.harmonics),
    sample_rate_hz=snakemake.params.sample_rate_hz, **examples, **out)
print(f"{method} {name}: merged {len(parts)} chunks, {int(out['fell'].sum())} fell",
      file=sys.stderr)
