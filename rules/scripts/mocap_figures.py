"""Snakemake script: Figures 4.2-4.11 (measured vs open-loop model, Sec 4.2)."""

import json
import sys

import numpy as np
import pandas as pd

from pedalrepro import figures, params, validation
from pedalrepro.figures import validation as fv

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
source = json.loads(open(snakemake.input.source).read())
reason = "" if source["data_source"] == "figshare" else source["reason"]
per_run_all = pd.read_csv(snakemake.input.per_run)
per_run = per_run_all[per_run_all.data_source == source["data_source"]]  # never pooled
series = np.load(snakemake.input.series)
lin = snakemake.params.ps_grid
v = np.arange(lin["ps_speed_step_m_s"], lin["ps_speed_max_m_s"] + 1e-9, lin["ps_speed_step_m_s"])
w = np.arange(lin["ps_omega_step_rad_s"], lin["ps_omega_max_rad_s"] + 1e-9,
              lin["ps_omega_step_rad_s"])
maps = {}
for system in params.MODELS:
    r, s = validation.ps_map(system, v, w)
    maps[system] = fv.PSMap(v, w, r, s)
out = {p.split("/")[-1].removesuffix(".png"): p for p in snakemake.output}
n_ex = int(snakemake.params.example_runs_per_system)
for system in params.MODELS:
    examples = []
    for _, row in validation.example_runs(per_run, system, n_ex).iterrows():
        rid = int(row.run_id)
        t = series[f"{rid}_t_s"]
        mr, ms = validation.model_series(system, row.speed_kmh / 3.6, series[f"{rid}_crank_rad"],
                                         row.cadence_rpm * np.pi / 30)
        examples.append(fv.ExampleRun(rid, row.speed_kmh, row.cadence_rpm, t,
                                      series[f"{rid}_roll_rad"], series[f"{rid}_steer_rad"],
                                      mr, ms))
    fs = float(1.0 / np.median(np.diff(examples[0].t_s)))
    f_time, f_freq = fv.SYSTEM_FIGURES[system]
    with figures.style():
        figures.save(fv.time_series(system, examples, maps[system], reason), out[f_time])
        figures.save(fv.frequency_domain(system, examples, maps[system], fs, reason),
                     out[f_freq])
with figures.style():
    figures.save(fv.fig_4_10(per_run, maps, reason), out["fig_4_10"])
    figures.save(fv.fig_4_11(per_run, reason), out["fig_4_11"])
real = validation.real_example(per_run_all, series)
with figures.style():
    if real is None:
        fig = fv.no_real_run("No real public-subset run in this build (data_source: "
                             f"{source['data_source']}; see the chapter's data note)")
    else:
        fig = fv.real_run_panel(real[0], real[1], f"REAL run {real[0].run_id}")
    figures.save(fig, out["real_run_panel"])
print("figures written:", sorted(out), file=sys.stderr)
