"""Speed of the non-linear time solutions (Sec 3.1.2.1): one 180 s NP run and the full sweep.

    python scripts/bench_nonlinear.py [--sample-stride 5] [--single-only] [--models HR CF]

Measures (thesis profile: 180 s at 100 Hz, config/config.yaml tolerances):
1. one 180 s NP run of each of ``--models`` (default HR and CF, the model with arm loops) at
   6 m/s, 6 rad/s: compiled whole-run RK45 (the sweep's path), and for HR solve_ivp with the
   compiled right-hand side (the reference path), at the default and at the thesis's SPACAR
   tolerances;
2. the full NT + NP sweep (4 models x 676 points x 2 methods) with 2 workers, extrapolated from
   runs on a sub-grid (every ``stride``-th speed and cadence) of the thesis grid for the models
   of ``pedalrepro.params.MODELS``, the four systems (CF and HS carry arm loops).
   The measured full sweep is Snakemake's own benchmark files (results/benchmarks/nonlinear_*).
Nothing is written; the numbers are printed.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pedalrepro import config, params, response
from pedalrepro.integrator import SPACAR_ATOL, SPACAR_RTOL
from pedalrepro.nonlinear import models, sweep
from pedalrepro.nonlinear.simulate import simulate


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sample-stride", type=int, default=5)
    ap.add_argument("--single-only", action="store_true", help="skip the sub-grid sweep")
    ap.add_argument("--models", nargs="+", default=["HR", "CF"])
    args = ap.parse_args()
    cfg = config.load()
    settings = sweep.RunSettings.from_config(cfg)
    spacar = sweep.RunSettings(settings.duration_s, settings.sample_rate_hz, SPACAR_RTOL,
                               SPACAR_ATOL, settings.fall_roll_rad)
    print(f"thesis profile: {settings.duration_s:g} s at {settings.sample_rate_hz:g} Hz, "
          f"rtol {settings.rtol:g}, atol {settings.atol:g}")
    for name in args.models:
        h = response.forcing(name, cfg["linear"]["harmonics"])
        models.np_model(name, 6.0)  # build/load the cached code outside the timings
        for label, s in (("default tolerances", settings), ("SPACAR tolerances", spacar)):
            sim, dt = timed(sweep.run, "NP", name, 6.0, 6.0, h, s)
            print(f"one 180 s NP run ({name}, 6 m/s, 6 rad/s), compiled RK45, {label}: "
                  f"{dt:.3f} s ({sim.n_rhs} rhs calls, {dt / sim.n_rhs * 1e6:.1f} us/call, "
                  f"fell={sim.fell} at {sim.t_end_s:.1f} s)")
    nl = models.np_model("HR", 6.0)
    sim, dt = timed(simulate, nl, 6.0, settings.duration_s, settings.sample_rate_hz,
                    rtol=settings.rtol, atol=settings.atol, fall_roll_rad=settings.fall_roll_rad,
                    compiled=False)
    print(f"same run with scipy solve_ivp(RK45) + compiled right-hand side: {dt:.2f} s "
          f"({sim.n_rhs} rhs calls)")
    if args.single_only:
        return

    lin = cfg["linear"]
    v, w = response.speed_cadence_grid(lin["time_speed_step_m_s"], lin["time_speed_max_m_s"],
                                       lin["time_omega_step_rad_s"], lin["time_omega_max_rad_s"])
    # zero cadence needs no run (no forcing): sample and count only the forced points
    w_forced = w[w > 0]
    vs, ws = v[:: args.sample_stride], w_forced[:: args.sample_stride]
    per_run = []
    for name in params.MODELS:
        hm = response.forcing(name, lin["harmonics"])
        for method in sweep.METHODS:
            out, dt = timed(sweep.grid_runs, method, name, vs, ws, hm, settings)
            n = vs.size * ws.size
            per_run.append(dt / n)
            print(f"{method} {name}: {n} sampled runs in {dt:.1f} s ({dt / n:.3f} s/run, "
                  f"{int(out['fell'].sum())} fell)")
    mean = float(np.mean(per_run))
    n_models = len(params.MODELS)
    n_full = n_models * v.size * w_forced.size * 2
    print(f"mean time per run on the sub-grid: {mean:.3f} s")
    print(f"full NT + NP sweep, {n_models} models x {v.size * w.size} x 2 ({n_full} forced "
          f"runs), 2 workers: ~{mean * n_full / 2 / 60:.1f} min")


if __name__ == "__main__":
    main()
