"""Every folder of the project, named once (the showyourwork ``paths`` pattern).

The results folder defaults to ``<repo>/results`` and can be moved with the environment variable
``PEDALREPRO_RESULTS`` (the Snakefile sets it from ``config["results_dir"]`` so that rule scripts,
notebooks and the book build all read and write the same place).

The layout inside the results folder (:data:`LAYOUT`) is defined here and nowhere else: the
Snakemake helpers of ``rules/common.smk`` (``table()``, ``figure()``, ``interm()``, ``logfile()``,
``bench()``) call these functions with ``root=`` the configured ``results_dir``, so a rule's
output and the path a notebook reads are the same string.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = [
    "ROOT", "DATA", "PARAMETERS", "PUBLISHED", "CONFIG", "NOTEBOOKS", "BOOK", "STYLE", "LAYOUT",
    "FIGURE_FORMATS", "results", "tables", "figures", "intermediate", "logs", "benchmarks", "table",
    "figure", "interm", "log", "benchmark", "last_runtime_s",
]

#: Repository root (the folder holding ``pyproject.toml``), for an editable install.
ROOT: Path = Path(__file__).resolve().parents[2]
DATA: Path = ROOT / "data"
PARAMETERS: Path = DATA / "parameters"
PUBLISHED: Path = DATA / "published"
CONFIG: Path = ROOT / "config"
NOTEBOOKS: Path = ROOT / "notebooks"
BOOK: Path = ROOT / "book"
#: The shared matplotlib style used by every figure.
STYLE: Path = Path(__file__).with_name("pedalrepro.mplstyle")

#: Sub-folders of the results folder: what goes where.
LAYOUT: dict[str, str] = {
    "tables": "tables",              # CSV tables, ids of data/figure_ids.yaml
    "figures": "figures",            # <id>.png (+ <id>.pdf, the vector copy)
    "intermediate": "intermediate",  # arrays (npz) shared between rules, figures, notebooks
    "logs": "logs",                  # one log per rule job
    "benchmarks": "benchmarks",      # Snakemake benchmark TSVs of sweeps and simulations
}
#: File suffixes of the figure files written by :func:`pedalrepro.figures.save`.
FIGURE_FORMATS: tuple[str, ...] = ("png", "pdf")


def results() -> Path:
    """Folder for everything the pipeline generates (``$PEDALREPRO_RESULTS`` or ``results/``)."""
    env = os.environ.get("PEDALREPRO_RESULTS")
    if env:
        path = Path(env)
        return path if path.is_absolute() else ROOT / path
    return ROOT / "results"


def _sub(kind: str, root: str | Path | None) -> Path:
    base = results() if root is None else Path(root)
    return base / LAYOUT[kind]


def tables(root: str | Path | None = None) -> Path:
    """``results/tables``: CSV tables (ids of ``data/figure_ids.yaml``, e.g. ``table_d_1.csv``).

    ``root``: another results folder (the Snakemake helpers pass ``config["results_dir"]``)."""
    return _sub("tables", root)


def figures(root: str | Path | None = None) -> Path:
    """``results/figures``: one PNG (and its PDF) per figure id (``fig_2_3.png``)."""
    return _sub("figures", root)


def intermediate(root: str | Path | None = None) -> Path:
    """``results/intermediate``: arrays (npz) shared between rules, figures and notebooks."""
    return _sub("intermediate", root)


def logs(root: str | Path | None = None) -> Path:
    """``results/logs``: one log file per rule job."""
    return _sub("logs", root)


def benchmarks(root: str | Path | None = None) -> Path:
    """``results/benchmarks``: Snakemake benchmark files (TSV)."""
    return _sub("benchmarks", root)


def table(figure_id: str, root: str | Path | None = None) -> Path:
    """Path of the CSV table with id ``figure_id`` (e.g. ``"table_d_1"``)."""
    return tables(root) / f"{figure_id}.csv"


def figure(figure_id: str, root: str | Path | None = None, fmt: str = "png") -> Path:
    """Path of the figure with id ``figure_id`` (e.g. ``"fig_2_3"``); ``fmt`` ``"png"`` or
    ``"pdf"`` (the vector copy written beside it)."""
    if fmt not in FIGURE_FORMATS:
        raise ValueError(f"figure format {fmt!r}: expected one of {FIGURE_FORMATS}")
    return figures(root) / f"{figure_id}.{fmt}"


def interm(name: str, root: str | Path | None = None) -> Path:
    """Path ``results/intermediate/<name>`` (``name`` may hold sub-folders and wildcards)."""
    return intermediate(root) / name


def log(name: str, root: str | Path | None = None) -> Path:
    """Path ``results/logs/<name>.log``."""
    return logs(root) / f"{name}.log"


def benchmark(name: str, root: str | Path | None = None) -> Path:
    """Path ``results/benchmarks/<name>.tsv``."""
    return benchmarks(root) / f"{name}.tsv"


def last_runtime_s(path: str | Path) -> float | None:
    """Wall time (s) of the last run recorded in a Snakemake benchmark file (first column of its
    last line), or None when there is no such file or it holds no number (the rules'
    ``longest_first`` priority, rules/common.smk)."""
    try:
        seconds = float(Path(path).read_text().splitlines()[-1].split("\t")[0])
    except (OSError, IndexError, ValueError):
        return None
    return seconds if seconds >= 0 else None
