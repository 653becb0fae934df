"""Snakemake script: derive the non-linear models and build their code once (cached on disk).

Later jobs load the generated Python module and the compiled library from the cache
(``pedalrepro.nonlinear.codegen.cache_dir()``); this job only makes sure they exist before the
parallel sweep jobs start, so that two jobs never derive the same model at once.
"""

import sys
import time

from pedalrepro.nonlinear import codegen, model

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
lines = []
for options in [model.ModelOptions(legs=legs, arms=arms) for arms in (False, True)
                for legs in (False, True)]:
    # plain Whipple (benchmark, HS, HR, CR) and with CF's arm loops, with and without legs
    start = time.perf_counter()
    py = codegen.generated_source(options)
    so = codegen.compiled_library(options)
    lines.append(f"{options.key()}: {py} {so} ({time.perf_counter() - start:.1f} s)")
with open(snakemake.output[0], "w") as fh:
    fh.write("\n".join(lines) + "\n")
print("\n".join(lines), file=sys.stderr)
