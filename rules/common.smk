# Shared set-up: config validation, the results folder, and helpers naming outputs and the
# library modules a rule imports (listed as inputs so that a physics edit reruns the rule).
import os
from pathlib import Path

from snakemake.utils import validate


validate(config, "../config/schema.yaml")

# Every script, notebook and the book build read the results folder from this variable
# (pedalrepro.paths.results()).
R = config["results_dir"].rstrip("/")
os.environ.update(PEDALREPRO_RESULTS=str(Path(R).resolve()))

PKG = "src/pedalrepro"
ROOT_DIR = Path(workflow.basedir)

# The published values and how the report checks them (pedalrepro.report.check): inputs of every
# rule that writes report rows.
PUBLISHED_CLAIMS = ["data/published/claims.yaml", "data/published/thesis_values.yaml",
                    "data/published/meijaard2007.yaml"]

# Filled by the rules/*.smk files: report parts and everything the book shows.
REPORT_PARTS = []
BOOK_INPUTS = []


def table(name):
    """results/tables/<name>.csv"""
    return f"{R}/tables/{name}.csv"


def figure(name):
    """results/figures/<name>.png"""
    return f"{R}/figures/{name}.png"


def interm(name):
    """results/intermediate/<name>"""
    return f"{R}/intermediate/{name}"


def logfile(name):
    return f"{R}/logs/{name}.log"


def bench(name):
    return f"{R}/benchmarks/{name}.tsv"


def pkg(*modules):
    """Source files of pedalrepro modules a rule uses (e.g. pkg("legs", "figures/section2"))."""
    return [f"{PKG}/__init__.py", f"{PKG}/paths.py", f"{PKG}/params.py"] + [
        f"{PKG}/{m}.py" for m in modules
    ]
