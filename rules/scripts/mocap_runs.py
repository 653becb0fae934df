"""Snakemake script: the treadmill run files (Sec 4.1), real where they can be had.

data_source (config): auto -> the figshare files when they can all be had, else the seeded
stand-in plus the real public-subset runs that can be had (labelled per row); figshare -> the
real files or one clear error, printed in Snakemake's output as well as the log (a corrupt
cached file named with the registry's hash and its own); synthetic -> the stand-in
(pedalrepro.mocap.prepare).
"""

import json
import sys
from pathlib import Path

from pedalrepro.mocap import fetch, prepare

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
try:
    record = prepare.prepare_runs(snakemake.params.data_source, snakemake.output.runs,
                                  snakemake.params.mocap, snakemake.params.seed)
except (fetch.DataUnavailableError, fetch.HashMismatchError) as exc:
    # the reason in Snakemake's own output (the job's original stderr), not only in the log
    for stream in (sys.stderr, sys.__stderr__):
        print(f"Error in rule mocap_runs: {exc}", file=stream, flush=True)
    raise SystemExit(1) from None
print(json.dumps(record, indent=1), file=sys.stderr)
Path(snakemake.output.source).write_text(json.dumps(record, indent=1) + "\n")
