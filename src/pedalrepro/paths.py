"""Every folder of the project, named once (the showyourwork ``paths`` pattern).

The results folder defaults to ``<repo>/results`` and can be moved with the environment variable
``PEDALREPRO_RESULTS`` (the Snakefile sets it from ``config["results_dir"]`` so that rule scripts,
notebooks and the book build all read and write the same place).
"""

from __future__ import annotations

import os
from pathlib import Path

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


def results() -> Path:
    """Folder for everything the pipeline generates (``$PEDALREPRO_RESULTS`` or ``results/``)."""
    env = os.environ.get("PEDALREPRO_RESULTS")
    if env:
        path = Path(env)
        return path if path.is_absolute() else ROOT / path
    return ROOT / "results"


def tables() -> Path:
    """``results/tables``: CSV tables (ids as in FIGURES.md, e.g. ``table_d_1.csv``)."""
    return results() / "tables"


def figures() -> Path:
    """``results/figures``: one PNG per figure id (``fig_2_3.png``)."""
    return results() / "figures"


def intermediate() -> Path:
    """``results/intermediate``: arrays (npz) shared between rules, figures and notebooks."""
    return results() / "intermediate"


def table(figure_id: str) -> Path:
    """Path of the CSV table with id ``figure_id`` (e.g. ``"table_d_1"``)."""
    return tables() / f"{figure_id}.csv"


def figure(figure_id: str) -> Path:
    """Path of the PNG figure with id ``figure_id`` (e.g. ``"fig_2_3"``)."""
    return figures() / f"{figure_id}.png"
