"""Snakemake script: execute one book notebook as jupyter-book did (pedalrepro.book
.execute_notebook: kernel python3 in the repository's notebooks/ folder, the book's timeout and
stderr setting) and write it, outputs kept, for the rule `book` to render."""

import sys
import traceback

from pedalrepro import book

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
try:
    seconds = book.execute_notebook(snakemake.input.notebook, snakemake.output[0],
                                    cwd=snakemake.params.cwd, timeout=snakemake.params.timeout,
                                    stderr_output=snakemake.params.stderr_output)
except RuntimeError as err:
    traceback.print_exc()  # the cell, its traceback and the notebook, into the log
    # ... and the cause on the console, as the jupyter-book build printed its log's tail
    print(f"{snakemake.input.notebook} failed (log: {snakemake.log[0]}):\n{str(err)[-4000:]}",
          file=sys.__stderr__)
    sys.exit(1)
print(f"Executed {snakemake.input.notebook} in {seconds:.2f} s -> {snakemake.output[0]}",
      file=sys.stderr)
