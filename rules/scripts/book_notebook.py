"""Snakemake script: execute one book notebook as jupyter-book did (pedalrepro.book
.execute_notebook: kernel python3 in the repository's notebooks/ folder, the book's timeout and
stderr setting) and write it, outputs kept, for the rule `book` to render."""

import os
import sys
import traceback

from pedalrepro import book

# The log takes this process's stderr and the kernel's (file descriptor 2, which the kernel
# inherits: its start-up warnings belong in the log, not on the console); the console keeps a
# copy for the failure's summary.
console = os.fdopen(os.dup(2), "w")
sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
os.dup2(sys.stderr.fileno(), 2)
try:
    seconds = book.execute_notebook(snakemake.input.notebook, snakemake.output[0],
                                    cwd=snakemake.params.cwd, timeout=snakemake.params.timeout,
                                    stderr_output=snakemake.params.stderr_output)
except RuntimeError as err:
    traceback.print_exc()  # the cell, its traceback and the notebook, into the log
    # ... and the cause on the console, as the jupyter-book build printed its log's tail
    text = str(err)  # the cell's source first, then its traceback
    if len(text) > 6000:
        text = f"{text[:2500]}\n[...]\n{text[-3000:]}"
    print(f"{snakemake.input.notebook} failed (log: {snakemake.log[0]}):\n{text}", file=console)
    console.flush()
    sys.exit(1)
print(f"Executed {snakemake.input.notebook} in {seconds:.2f} s -> {snakemake.output[0]}",
      file=sys.stderr)
