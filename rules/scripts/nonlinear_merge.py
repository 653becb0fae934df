"""Snakemake script: join the chunks of an NT/NP sweep and add the six example runs.

Writes results/intermediate/time/<method>_<model>.npz in the format of CONTRIBUTING.md.
"""

import sys

import numpy as np

from pedalrepro import evaluation, response
from pedalrepro.nonlinear import sweep

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
method, name = snakemake.wildcards.method, snakemake.wildcards.model
v, w = response.speed_cadence_grid(**snakemake.params.grid)
parts = [np.load(p) for p in snakemake.input.chunks]
out = {k: np.concatenate([p[k] for p in parts]) for k in
       ("roll_amp_rad", "steer_amp_rad", "t_end_s", "fell", "n_rhs")}
order = np.concatenate([p["speed_index"] for p in parts])
if not np.array_equal(np.sort(order), np.arange(v.size)):
    raise ValueError(f"chunks of {method}_{name} do not cover the speed grid")
out = {k: a[np.argsort(order)] for k, a in out.items()}
settings = sweep.RunSettings(**snakemake.params.settings)
h = response.forcing(name, snakemake.params.harmonics)
pts = evaluation.example_points(name)
t = response.time_samples(settings.duration_s, settings.sample_rate_hz)
ex_roll = np.full((pts.speed_m_s.size, t.size), np.nan)
ex_steer = np.full_like(ex_roll, np.nan)
ex_end = np.zeros(pts.speed_m_s.size)
ex_fell = np.zeros(pts.speed_m_s.size, bool)
for k, (vk, wk) in enumerate(zip(pts.speed_m_s, pts.omega_rad_s, strict=True)):
    sim = sweep.run(method, name, vk, wk, h, settings)
    if sim is None:
        ex_roll[k], ex_steer[k], ex_end[k] = 0.0, 0.0, t[-1]
        continue
    n = min(t.size, sim.t_s.size)
    ex_roll[k, :n], ex_steer[k, :n] = sim.roll_rad[:n], sim.steer_rad[:n]
    ex_end[k], ex_fell[k] = sim.t_end_s, sim.fell
np.savez_compressed(
    snakemake.output[0], speed_m_s=v, omega_rad_s=w, method=method, model=name,
    harmonics=h.n, sample_rate_hz=settings.sample_rate_hz,
    example_speed_m_s=pts.speed_m_s, example_omega_rad_s=pts.omega_rad_s, example_t_s=t,
    example_roll_rad=ex_roll, example_steer_rad=ex_steer, example_t_end_s=ex_end,
    example_fell=ex_fell, **out)
print(f"{method} {name}: merged {len(parts)} chunks, {int(out['fell'].sum())} fell",
      file=sys.stderr)
