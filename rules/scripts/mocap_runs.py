"""Snakemake script: the treadmill run files (Sec 4.1), real or synthetic stand-in.

data_source (config): auto -> the figshare files when cached or downloadable, else the seeded
stand-in (pedalrepro.mocap.synthetic) with the reason; figshare -> the real files or a clear
error; synthetic -> the stand-in. Writes the run files (or links to the pooch cache) into the
output folder and source.json = {data_source, reason}.
"""

import json
import sys
from pathlib import Path

from pedalrepro.mocap import fetch, synthetic

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
out = Path(snakemake.output.runs)
out.mkdir(parents=True, exist_ok=True)
source, reason = fetch.resolve_source(snakemake.params.data_source)
print(f"data source: {source} ({reason})", file=sys.stderr)
if source == "figshare":
    files = fetch.run_files()
    for run_id, path in sorted(files.items()):
        link = out / f"{run_id:04d}.mat"
        if not link.exists():
            link.symlink_to(Path(path).resolve())
    print(f"{len(files)} run files linked from the pooch cache", file=sys.stderr)
else:
    index = synthetic.write_stand_in(out, snakemake.params.mocap, snakemake.params.seed)
    print(index.to_string(), file=sys.stderr)
Path(snakemake.output.source).write_text(json.dumps({"data_source": source, "reason": reason},
                                                     indent=1) + "\n")
