"""Snakemake script: write the configuration in effect to <results>/config.used.yaml
(pedalrepro.config.COPY_NAME; config.write refuses a path inside a source of the repository)."""

import json
import sys

from pedalrepro import config

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
print(config.write(json.loads(snakemake.params.config), snakemake.output[0]), file=sys.stderr)
