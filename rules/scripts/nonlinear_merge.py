"""Snakemake script: join the chunks of an NT/NP sweep and add the six example runs and the
one-speed series (Figs 3.18, 3.19, 3.28, 3.29).

Writes results/intermediate/time/<method>_<model>.npz in the format of CONTRIBUTING.md.
"""

import sys

import numpy as np

from pedalrepro import evaluation, response
from pedalrepro.nonlinear import calibration, sweep

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.use_file(snakemake.input.calibration)  # frames calibrated to Appendix B
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


def runs(speeds, omegas):
    """Time histories of (speed, cadence) runs: roll, steer (NaN after a fall), end, fell."""
    roll = np.full((len(speeds), t.size), np.nan)
    steer = np.full_like(roll, np.nan)
    end = np.zeros(len(speeds))
    fell = np.zeros(len(speeds), bool)
    for k, (vk, wk) in enumerate(zip(speeds, omegas, strict=True)):
        sim = sweep.run(method, name, vk, wk, h, settings)
        if sim is None:
            roll[k], steer[k], end[k] = 0.0, 0.0, t[-1]
            continue
        n = min(t.size, sim.t_s.size)
        roll[k, :n], steer[k, :n] = sim.roll_rad[:n], sim.steer_rad[:n]
        end[k], fell[k] = sim.t_end_s, sim.fell
    return roll, steer, end, fell


ex_roll, ex_steer, ex_end, ex_fell = runs(pts.speed_m_s, pts.omega_rad_s)
# the one-speed series of Figs 3.18, 3.19, 3.28, 3.29 (as linear_time writes for LA and LN)
series_v = np.full(len(pts.series_omega_rad_s), pts.series_speed_m_s)
se_roll, se_steer, se_end, se_fell = runs(series_v, pts.series_omega_rad_s)
np.savez_compressed(
    snakemake.output[0], speed_m_s=v, omega_rad_s=w, method=method, model=name,
    harmonics=h.n, sample_rate_hz=settings.sample_rate_hz,
    example_speed_m_s=pts.speed_m_s, example_omega_rad_s=pts.omega_rad_s, example_t_s=t,
    example_roll_rad=ex_roll, example_steer_rad=ex_steer, example_t_end_s=ex_end,
    example_fell=ex_fell, series_speed_m_s=series_v, series_omega_rad_s=pts.series_omega_rad_s,
    series_roll_rad=se_roll, series_steer_rad=se_steer, series_t_end_s=se_end,
    series_fell=se_fell, **out)
print(f"{method} {name}: merged {len(parts)} chunks, {int(out['fell'].sum())} fell",
      file=sys.stderr)
