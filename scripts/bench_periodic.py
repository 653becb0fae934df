"""Speed of the periodic orbits (pedalrepro.periodic) against the NT/NP simulation sweeps.

    python scripts/bench_periodic.py [--models HR] [--methods NT NP] [--stride 1]
                                     [--results results]

Measures on this machine (nothing is written; the numbers are printed):
1. ms per orbit (wall and CPU time: the CPU time is the fair figure on a shared machine), median
   over the thesis time grid (config ``linear.time_*``; every
   ``--stride``-th speed and cadence) for each of ``--methods`` and ``--models`` (model set-up
   and the compiled driver's build excluded; NP includes building its leg motion per cadence);
2. the full orbit map time of those models and methods, extrapolated to the four models of
   ``pedalrepro.params.MODELS`` when fewer are measured;
3. side by side on every ``--sweep-stride``-th speed and cadence, the CPU time of today's NT/NP
   simulation sweep (``sweep.grid_runs``, the thesis profile's 180 s runs) and of the orbits;
4. the job time of today's NT + NP sweeps and of the periodic map jobs from
   Snakemake's benchmark files (``<results>/benchmarks/nonlinear_time_*.tsv``,
   ``periodic_map_thesis_*.tsv``), when a thesis-profile run left them.
"""

from __future__ import annotations

import argparse
import csv
import os
import time
from pathlib import Path

import numpy as np

from pedalrepro import config, params, paths, periodic, response


def job_seconds(folder: Path, pattern: str) -> tuple[float, float, int]:
    """Sums of the wall (``s``) and ``cpu_time`` columns of Snakemake benchmark files matching
    ``pattern``, and their count."""
    total, cpu, n = 0.0, 0.0, 0
    for f in sorted(folder.glob(pattern)):
        with f.open() as fh:
            rows = list(csv.DictReader(fh, delimiter="\t"))
        if rows:
            total += float(rows[0]["s"])
            cpu += float(rows[0].get("cpu_time") or "nan")
            n += 1
    return total, cpu, n


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", nargs="+", default=["HR"])
    ap.add_argument("--methods", nargs="+", default=["NT", "NP"])
    ap.add_argument("--stride", type=int, default=1)
    ap.add_argument("--results", default="results")
    ap.add_argument("--sweep-stride", type=int, default=5,
                    help="also time today's NT/NP simulation sweep (sweep.grid_runs) of the same "
                         "models on every n-th speed and cadence, CPU time beside the orbits' "
                         "on the same points (0: skip)")
    args = ap.parse_args()
    cfg = config.load()
    lin = cfg["linear"]
    v0 = response.grid(lin["time_speed_step_m_s"], lin["time_speed_max_m_s"])
    w0 = response.grid(lin["time_omega_step_rad_s"], lin["time_omega_max_rad_s"])
    v, w = v0[::args.stride], w0[::args.stride]
    pc = cfg["periodic"]
    print(f"thesis time grid{' (sub-grid)' if args.stride > 1 else ''}: {v.size} speeds x "
          f"{w.size} cadences; rtol {pc['rtol']:g}, max_growth {pc['max_growth']:g}")
    map_s: dict[str, float] = {}
    map_cpu: dict[str, float] = {}
    for method in args.methods:
        for model in args.models:
            periodic.OrbitSolver(model, method, 2 * np.pi)  # load/compile outside the timings
            start, cpu0 = time.perf_counter(), time.process_time()
            out = periodic.orbit_map(model, method, v, w, rtol=pc["rtol"],
                                     max_growth=pc["max_growth"])
            elapsed = time.perf_counter() - start
            map_cpu[f"{method}_{model}"] = time.process_time() - cpu0
            forced = np.broadcast_to(w[None, :] > 0, out["converged"].shape)
            ms = 1e3 * out["orbit_time_s"][forced]
            cpu = 1e3 * out["orbit_cpu_s"][forced]
            conv = out["converged"] & forced
            map_s[f"{method}_{model}"] = elapsed
            print(f"{method} {model}: {ms.size} orbits, {int(conv.sum())} converged, median "
                  f"{np.median(ms):.1f} ms/orbit wall, {np.median(cpu):.1f} ms CPU (p90 "
                  f"{np.percentile(cpu, 90):.1f} ms CPU), "
                  f"max residual {np.nanmax(out['residual'][conv]):.1e}, mean Newton iterations "
                  f"{np.mean(out['iterations'][forced]):.2f}, map {elapsed:.1f} s wall, "
                  f"{map_cpu[f'{method}_{model}']:.1f} s CPU")
    n_models = len(params.MODELS)
    scale = n_models / len(args.models) * args.stride**2
    total = sum(map_s.values()) * scale
    total_cpu = sum(map_cpu.values()) * scale
    print(f"full {'+'.join(args.methods)} orbit maps of {n_models} models on the thesis grid: "
          f"{total:.0f} s wall, {total_cpu:.0f} s CPU (extrapolated x{scale:g}; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs)")
    if args.sweep_stride:
        from pedalrepro.nonlinear import sweep

        settings = sweep.RunSettings.from_config(cfg)
        vs, ws = v0[::args.sweep_stride], w0[::args.sweep_stride]
        for method in args.methods:
            for model in args.models:
                h = response.forcing(model, harmonics=tuple(lin["harmonics"]))
                c0 = time.process_time()
                sweep.grid_runs(method, model, vs, ws, h, settings)
                sim_cpu = time.process_time() - c0
                c0 = time.process_time()
                periodic.orbit_map(model, method, vs, ws, rtol=pc["rtol"],
                                   max_growth=pc["max_growth"])
                orb_cpu = time.process_time() - c0
                print(f"side by side on {vs.size} x {ws.size} points, {method} {model}: "
                      f"simulation sweep ({settings.duration_s:g} s runs) {sim_cpu:.1f} s CPU, "
                      f"orbits {orb_cpu:.1f} s CPU (ratio {sim_cpu / orb_cpu:.1f})")
    bench = paths.benchmarks(args.results)
    sweep_s, sweep_cpu, n_sweep = job_seconds(bench, "nonlinear_time_chunk_N[TP]_*_*.tsv")
    maps_s, maps_cpu, n_maps = job_seconds(bench, "periodic_map_thesis_*.tsv")
    if n_sweep:
        print(f"today's NT + NP simulation sweeps: {sweep_s:.0f} s of job time, {sweep_cpu:.0f} "
              f"s CPU ({n_sweep} benchmark files in {bench})")
    else:
        print(f"no NT/NP sweep benchmark files in {bench} (run the thesis profile)")
    if n_maps:
        print(f"periodic map jobs (thesis grid): {maps_s:.0f} s of job time, {maps_cpu:.0f} s "
              f"CPU ({n_maps} files)")


if __name__ == "__main__":
    main()
