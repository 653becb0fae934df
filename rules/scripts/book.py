"""Snakemake script: build the jupyter-book, strictly, from a staging copy of book/ whose
notebooks are the executed ones (pedalrepro.book.stage_source: only the MyST text notebooks
book/*.md are executed here), then copy the figures and tables beside the pages."""

import shutil
import subprocess
import sys
from pathlib import Path

from pedalrepro import book

log = snakemake.log[0]
out = Path(snakemake.params.out)
source = Path(snakemake.input.config).parent  # book/
src = book.stage_source(source, snakemake.input.notebooks, snakemake.params.src)
exe = shutil.which("jupyter-book", path=str(Path(sys.executable).parent)) or "jupyter-book"
with open(log, "w") as fh:
    print(f"Staged {source} with {len(snakemake.input.notebooks)} executed notebooks in {src}",
          file=fh, flush=True)
    proc = subprocess.run([exe, "build", "--all", "-W", "-n", "--keep-going", str(src),
                           "--path-output", str(out)], stdout=fh, stderr=subprocess.STDOUT)
if proc.returncode != 0:
    lines = Path(log).read_text(errors="replace").splitlines()
    print("\n".join(lines[-40:]), file=sys.stderr)
    sys.exit(1)
html = Path(snakemake.output[0]).parent
# Sphinx copies each page's source beside it (_sources/): for a notebook, the repository's
# notebook as the single build copied it, not the executed one with its outputs (10x larger)
for nb in snakemake.input.notebooks:
    copied = html / "_sources" / "notebooks" / Path(nb).name
    if copied.is_file():
        shutil.copy2(source / "notebooks" / Path(nb).name, copied)
# Every figure in the book links its full-size PNG and its PDF, served from _build/html/figures/
# (pedalrepro.figures.BOOK_FIGURES_HREF), every table its CSV from _build/html/tables/
# (BOOK_TABLES_HREF); the page Downloads lists them all.
for name in ("figures", "tables"):
    folder = Path(getattr(snakemake.params, name))
    (html / name).mkdir(parents=True, exist_ok=True)
    if folder.is_dir():
        shutil.copytree(folder, html / name, dirs_exist_ok=True)
