"""Snakemake script: time solutions LA (analytic) or LN (numerical) of linear models.

Writes results/intermediate/time/<method>_<model>.npz with pedalrepro.timesolution.write (the
keys, optional ones included, are listed there).
"""

import sys
import time

import numpy as np

from pedalrepro import evaluation, linear, response, timesolution

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
method = snakemake.params.method
v, w = response.speed_cadence_grid(**snakemake.params.grid)
t = response.time_samples(**snakemake.params.samples)
fs = snakemake.params.samples["sample_rate_hz"]
fall = snakemake.params.fall_roll_rad
# LN only: ode tolerances of the sweep and of the example-point check (config linear.*tol)
lin = snakemake.params.tolerances if method == "LN" else {}


def time_solutions(name: str) -> dict:
    """Every array of one model's time-solution file."""
    model = linear.linear_model(name)
    h = response.forcing(name, snakemake.params.harmonics)
    h1 = response.select(h, (1,))
    pts = evaluation.example_points(name)

    def solve(vv, ww, harmonics, **tol):
        if method == "LA":
            return response.analytic_time_solution(model, vv, ww, harmonics, t, fall)
        return response.numerical_time_solutions(model, vv, ww, harmonics, t, fall_roll_rad=fall,
                                                 rtol=tol.get("rtol", lin["rtol"]),
                                                 atol=tol.get("atol", lin["atol"]))

    def runs(speeds, omegas, harmonics, **tol):
        sols = [solve(np.array([a]), np.array([b]), harmonics, **tol)
                for a, b in zip(speeds, omegas, strict=True)]
        return (np.stack([s.roll_rad[0, 0] for s in sols]),
                np.stack([s.steer_rad[0, 0] for s in sols]),
                np.array([s.t_end_s[0, 0] for s in sols]), np.array([s.fell[0, 0] for s in sols]))

    start = time.perf_counter()
    sol = solve(v, w, h)
    roll_amp, steer_amp = response.cadence_amplitudes(sol, fs, "hann")
    roll_rect, steer_rect = response.cadence_amplitudes(sol, fs, None)
    elapsed = time.perf_counter() - start
    out = dict(speed_m_s=v, omega_rad_s=w, roll_amp_rad=roll_amp, steer_amp_rad=steer_amp,
               roll_amp_rect_rad=roll_rect, steer_amp_rect_rad=steer_rect,
               t_end_s=sol.t_end_s, fell=sol.fell, method=method, model=name,
               harmonics=h.n, sample_rate_hz=fs)
    del sol
    ex_r, ex_s, ex_end, ex_fell = runs(pts.speed_m_s, pts.omega_rad_s, h)
    out.update(example_speed_m_s=pts.speed_m_s, example_omega_rad_s=pts.omega_rad_s,
               example_t_s=t, example_roll_rad=ex_r, example_steer_rad=ex_s,
               example_t_end_s=ex_end, example_fell=ex_fell)
    series_v = np.full(len(pts.series_omega_rad_s), pts.series_speed_m_s)
    se_r, se_s, se_end, _ = runs(series_v, pts.series_omega_rad_s, h)
    out.update(series_speed_m_s=series_v, series_omega_rad_s=pts.series_omega_rad_s,
               series_roll_rad=se_r, series_steer_rad=se_s, series_t_end_s=se_end)
    if method == "LA":
        s1 = solve(v, w, h1)
        out["roll_amp_h1_rad"], out["steer_amp_h1_rad"] = response.cadence_amplitudes(s1, fs)
        del s1
        e1_r, e1_s, _, _ = runs(pts.speed_m_s, pts.omega_rad_s, h1)
        out.update(example_roll_h1_rad=e1_r, example_steer_h1_rad=e1_s)
    else:
        et_r, et_s, _, _ = runs(pts.speed_m_s, pts.omega_rad_s, h, rtol=lin["tight_rtol"],
                                atol=lin["tight_atol"])
        out.update(example_roll_tight_rad=et_r, example_steer_tight_rad=et_s)
    print(f"{method} {name}: {v.size * w.size} runs in {elapsed:.2f} s, "
          f"{int(out['fell'].sum())} fell", file=sys.stderr)
    return out


paths = snakemake.output.npz
paths = [paths] if isinstance(paths, str) else list(paths)
for name, path in zip(snakemake.params.models, paths, strict=True):
    timesolution.write(path, time_solutions(name))
