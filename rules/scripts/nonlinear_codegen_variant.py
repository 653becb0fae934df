"""Snakemake script: derive one non-linear model variant and build its code once (cached).

Later jobs load the generated Python module and the compiled library from the cache
(``pedalrepro.nonlinear.codegen.cache_dir()``); this job only makes sure they exist before the
parallel sweep jobs start, so that two jobs never derive the same model at once.
"""

import sys
import time

from pedalrepro.nonlinear import codegen, library, symbolic

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
# plain Whipple (benchmark, HS, HR, CR) and with CF's arm loops, with and without legs
variant = snakemake.wildcards.variant
options = symbolic.ModelOptions(legs="legs" in variant, arms="arms" in variant)
start = time.perf_counter()
py = codegen.generated_source(options)
so = library.compiled_library(options)
line = f"{options.key()}: {py} {so} ({time.perf_counter() - start:.1f} s)"
with open(snakemake.output[0], "w") as fh:
    fh.write(line + "\n")
print(line, file=sys.stderr)
