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

# Filled by the rules/*.smk files: report parts and everything the book shows.
REPORT_PARTS = []
BOOK_INPUTS = []


# The results layout is defined once, in pedalrepro.paths (LAYOUT); these helpers only bind it to
# the configured results folder R (relative paths stay relative, as Snakemake targets).
from pedalrepro import paths as _paths


def table(name):
    """results/tables/<name>.csv"""
    return str(_paths.table(name, root=R))


def figure(name, fmt="png"):
    """results/figures/<name>.png (fmt="pdf": its vector copy)"""
    return str(_paths.figure(name, root=R, fmt=fmt))


def interm(name):
    """results/intermediate/<name>"""
    return str(_paths.interm(name, root=R))


def logfile(name):
    return str(_paths.log(name, root=R))


def bench(name):
    return str(_paths.benchmark(name, root=R))


def pkg(*modules):
    """Source files of pedalrepro modules a rule uses (e.g. pkg("legs", "figures/section2"))."""
    return [f"{PKG}/__init__.py", f"{PKG}/paths.py", f"{PKG}/params.py"] + [
        f"{PKG}/{m}.py" for m in modules
    ]
