"""Snakemake script: linearise the non-linear models (Sec 3.1.1.3 verification step).

benchmark_linearisation.csv: M, C1, K0, K2 of the non-linear benchmark model (16 rows).
linearisation_vs_appendix_b.csv: the project's HR/CR linearisations beside thesis Appendix B.
linearisation_own.npz: the project's matrices of every non-linear model (for PS/LA of its own
linear limit in the report).
"""

import sys

import numpy as np
import pandas as pd

from pedalrepro import params
from pedalrepro.nonlinear import parameters as nlp
from pedalrepro.nonlinear.numeric import NonlinearModel, benchmark_matrices

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
NAMES = ("M", "C1", "K0", "K2")


def rows(mats):
    return [(k, i, j, float(mats[k][i, j])) for k in NAMES for i in range(2) for j in range(2)]


bench = benchmark_matrices(NonlinearModel(params.benchmark_parameters("benchmark")))
pd.DataFrame(rows(bench), columns=["matrix", "i", "j", "value"]).to_csv(
    snakemake.output.benchmark, index=False)

records, own = [], {"benchmark": bench}
for name in snakemake.params.models:
    mats = benchmark_matrices(NonlinearModel(nlp.bicycle_rider(name)))
    own[name] = mats
    ab = params.appendix_b_model(name)
    for k, i, j, value in rows(mats):
        ref = float(getattr(ab, k)[i, j])
        # Appendix B prints round-off (|x| < 1e-12) where the exact value is zero
        rel = abs(value - ref) / abs(ref) if abs(ref) > 1e-12 else np.nan
        records.append((name, k, i, j, value, ref, rel))
pd.DataFrame(records, columns=["model", "matrix", "i", "j", "project", "appendix_b", "rel_diff"]
             ).to_csv(snakemake.output.appendix_b, index=False)
np.savez(snakemake.output.own, **{f"{m}_{k}": v[k] for m, v in own.items() for k in NAMES})
print("benchmark and", list(snakemake.params.models), "linearised", file=sys.stderr)
