"""Snakemake script: linearise the non-linear models (Sec 3.1.1.3 verification step).

benchmark_linearisation.csv: M, C1, K0, K2 of the non-linear benchmark model (16 rows).
linearisation_vs_appendix_b.csv: the project's HR/CR linearisations beside thesis Appendix B.
nonlinear_checks.csv: the linearisation and energy checks as numbers for the book.
linearisation_own.npz: the project's matrices of every non-linear model (for PS/LA of its own
linear limit in the report).
"""

import sys

import numpy as np
import pandas as pd
import yaml

from pedalrepro import params
from pedalrepro.nonlinear import parameters as nlp
from pedalrepro.nonlinear.numeric import NonlinearModel, benchmark_matrices
from pedalrepro.simulate import simulate

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
NAMES = ("M", "C1", "K0", "K2")


def rows(mats):
    return [(k, i, j, float(mats[k][i, j])) for k in NAMES for i in range(2) for j in range(2)]


meijaard = yaml.safe_load(open(snakemake.input.meijaard))
bench = benchmark_matrices(NonlinearModel(params.benchmark_parameters("benchmark")))
pd.DataFrame(rows(bench), columns=["matrix", "i", "j", "value"]).to_csv(
    snakemake.output.benchmark, index=False)

records, own = [], {"benchmark": bench}
for name in snakemake.params.models:
    mats = benchmark_matrices(NonlinearModel(nlp.legs_fixed(name)))
    own[name] = mats
    ab = params.appendix_b_model(name)
    for k, i, j, value in rows(mats):
        ref = float(getattr(ab, k)[i, j])
        # Appendix B prints round-off (|x| < 1e-12) where the exact value is zero
        rel = abs(value - ref) / abs(ref) if abs(ref) > 1e-12 else np.nan
        records.append((name, k, i, j, value, ref, rel))
pd.DataFrame(records, columns=["model", "matrix", "i", "j", "project", "appendix_b", "rel_diff"]
             ).to_csv(snakemake.output.appendix_b, index=False)
# Energy check (no dissipation, rolling without slip): unforced benchmark run from a stable
# state at 5 m/s with a roll-rate perturbation, 15 s, rtol = atol = 1e-10 (DOP853).
nl = NonlinearModel(params.benchmark_parameters("benchmark"))
x0 = nl.upright_state(5.0, roll_rate_rad_s=0.5)
sim = simulate(nl, 5.0, 15.0, 20.0, x0=x0, rtol=1e-10, atol=1e-10, method="DOP853")
energy = np.array([nl.energy_J(t, sim.states[:, k]) for k, t in enumerate(sim.t_s)])
drift = float(np.max(np.abs(energy - energy[0])) / abs(energy[0]))
pd.DataFrame([
    ("benchmark_linearisation_max_abs_diff", max(
        abs(v - meijaard[k][i][j]) for k, i, j, v in rows(bench)), "Meijaard 2007, 16 entries"),
    ("energy_relative_drift", drift, "unforced benchmark, 5 m/s, roll rate 0.5 rad/s, 15 s"),
    ("energy_J", float(energy[0]), "total mechanical energy of that run"),
] + [(f"appendix_b_max_rel_diff_{m}", float(np.nanmax([r[6] for r in records if r[0] == m])),
      "largest relative difference of the 16 entries (exact zeros excluded)")
     for m in snakemake.params.models], columns=["check", "value", "what"]).to_csv(
    snakemake.output.checks, index=False)
np.savez(snakemake.output.own, **{f"{m}_{k}": v[k] for m, v in own.items() for k in NAMES})
print("benchmark and", list(snakemake.params.models), "linearised", file=sys.stderr)
