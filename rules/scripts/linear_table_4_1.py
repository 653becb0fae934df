"""Snakemake script: Table 4.1 model columns from the particular solution (Sec 4.1, Eq 3.14-3.15),
and the same columns with the inputs chosen with Table 4.1 in view moved (pedalrepro.sensitivity).

Runs (system, speed, cadence) from data/parameters/validation_runs.yaml (Table 4.1 header).
"""

import sys

import pandas as pd

from pedalrepro import params, sensitivity

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
data = params.read_yaml(snakemake.input.runs)
runs = data["table_4_1"]
harmonics = snakemake.params.harmonics
df = sensitivity.table_4_1_model(runs, harmonics)
df.to_csv(snakemake.output.table, index=False, float_format="%.8f")
print(df.to_string(), file=sys.stderr)
moved = []
for variant in sensitivity.table_4_1_variants(data["cr_cadence_rpm_text_order"]):
    v = sensitivity.table_4_1_model(runs, harmonics, variant)
    v.insert(0, "variant", variant.name)
    v.insert(1, "chosen_input", variant.chosen_input)
    v.insert(2, "description", variant.description)
    moved.append(v)
out = pd.concat(moved, ignore_index=True)
out.to_csv(snakemake.output.moved, index=False, float_format="%.8f")
print(out.to_string(), file=sys.stderr)
