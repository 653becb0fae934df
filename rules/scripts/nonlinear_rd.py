"""Snakemake script: RD maps of the non-linear evaluation points 1a, 1b, PS vs NP (Fig 3.34).

One call of pedalrepro.evaluation.nonlinear_rd_maps on the NT/NP grids and the project's own
linearisation of each non-linear model; the report rule and fig_3_34 read the result.
"""

import sys

import numpy as np

from pedalrepro import evaluation, params, response

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
own = np.load(snakemake.input.own)
models = list(snakemake.params.models)
samples = snakemake.params.samples
maps, ranges = evaluation.nonlinear_rd_maps(
    {m: params.LinearModel(m, *(own[f"{m}_{k}"] for k in ("M", "C1", "K0", "K2")))
     for m in models},
    {m: np.load(snakemake.input.time[2 * i]) for i, m in enumerate(models)},
    {m: np.load(snakemake.input.time[2 * i + 1]) for i, m in enumerate(models)},
    {m: response.forcing(m, snakemake.params.harmonics) for m in models},
    *response.speed_cadence_grid(**snakemake.params.grid), response.time_samples(**samples),
    samples["sample_rate_hz"], snakemake.params.fall_roll_rad)
for m in models:
    print(m, "stable ranges of the own linearisation", ranges[m], file=sys.stderr)
np.savez(snakemake.output.maps, **maps)
