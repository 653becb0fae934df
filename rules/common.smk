# Shared set-up: config validation (schema + cross-key rules), the results folder, helpers naming
# outputs, and code_inputs(): the code and data inputs of a rule, computed from its script's
# import closure (never listed by hand, so they cannot drift from the code).
import os
from pathlib import Path

from pedalrepro import config as pconfig
from pedalrepro import dependencies


# config/schema.yaml (every error, its key named as linear.harmonics[1]: pedalrepro.config.validate)
pconfig.validate(config, Path(workflow.basedir) / "config" / "schema.yaml")
# NaN/inf, sample rate vs low-pass and harmonics (Nyquist), steps below maxima, results_dir (not
# a system folder, not inside or on a tracked source of the repository):
# each failure names its key (pedalrepro.config.check).
pconfig.check(config)
# One key order for every params dict (Snakemake compares params by repr): the same values in
# another order, e.g. from another merge of the same files, must not rerun a rule.
_canonical = pconfig.canonical(config)
config.clear()
config.update(_canonical)

# Every script, notebook and the book build read the results folder from this variable
# (pedalrepro.paths.results()).
R = config["results_dir"].rstrip("/")
os.environ.update(PEDALREPRO_RESULTS=str(Path(R).resolve()))

PKG = "src/pedalrepro"
ROOT_DIR = Path(workflow.basedir)
RULES_DIR = Path(workflow.basedir) / "rules"
#: The configuration in effect, written by rule write_config; notebooks read this copy.
CONFIG_COPY = f"{R}/{pconfig.COPY_NAME}"

# Filled by the rules/*.smk files: report parts and everything the book shows.
REPORT_PARTS = []
BOOK_INPUTS = []


def code_inputs(*sources):
    """The code and data inputs of a rule running ``sources`` (paths relative to rules/, like
    ``script:``, e.g. "scripts/linear_eigen.py"; notebooks too): the files themselves, every
    src/pedalrepro module in their import closure (imports inside functions included, package
    __init__.py files too) and every file those modules declare in DATA_FILES
    (pedalrepro.dependencies). Relative to the working directory, sorted."""
    return dependencies.code_inputs(*(RULES_DIR / s for s in sources), root=ROOT_DIR)


def cfg(section, *keys):
    """{key: config[section][key]} for the given keys: a rule's `params:` entry, so that the rule
    reruns exactly when one of the values it uses changes."""
    return {k: config[section][k] for k in keys}


def grid_params(prefix):
    """Keyword arguments of pedalrepro.response.speed_cadence_grid for the "ps" or "time" grid."""
    lin = config["linear"]
    return dict(speed_step_m_s=lin[f"{prefix}_speed_step_m_s"],
                speed_max_m_s=lin[f"{prefix}_speed_max_m_s"],
                omega_step_rad_s=lin[f"{prefix}_omega_step_rad_s"],
                omega_max_rad_s=lin[f"{prefix}_omega_max_rad_s"])


# params of the linear grids and sampling (keyword arguments of the pedalrepro.response functions)
PS_GRID = grid_params("ps")
TIME_GRID = grid_params("time")
EIGEN_SPEEDS = dict(step=config["linear"]["eigen_speed_step_m_s"],
                    maximum=config["linear"]["eigen_speed_max_m_s"])
TIME_SAMPLES = cfg("linear", "duration_s", "sample_rate_hz")
HARMONICS = list(config["linear"]["harmonics"])


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


def longest_first(name, fallback=lambda wildcards: 0.0):
    """A rule's ``priority:``: the seconds its job took last time (the first column of its
    benchmark file ``bench(name)``, wildcards filled in), ``fallback(wildcards)`` for a job not
    run here yet. Snakemake starts the job of highest priority first, so long jobs no longer
    start last and leave the other cores idle (longest-processing-time-first; the job times
    are in results/benchmarks). Only the order changes, never an output."""

    def priority(wildcards):
        last = _paths.last_runtime_s(bench(name.format(**wildcards)))
        return float(fallback(wildcards)) if last is None else last

    return priority
