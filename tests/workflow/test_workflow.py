"""End to end: the quick profile builds the whole book from a fresh results folder.

The run itself is the session fixture ``quick_workflow`` (tests/conftest.py), shared with the
browser test (tests/workflow/test_book_browser.py), which then opens that very book.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from required import REAL, required

from pedalrepro import paths, report

pytestmark = pytest.mark.workflow

#: The only lint snakemake may report: this project ships one hashed environment.lock instead of
#: per-rule conda environments or containers (README, "Layout").
ALLOWED_LINT = "Specify a conda environment or container for each rule."


#: Report rows of the REAL public-subset run; they exist only when the data folder
#: ($PEDALREPRO_DATA_DIR) holds the public subset (data/registry_public.txt), as in CI.
REAL_ROW_PREFIX = "table_4_1.real_run_"
DATA_DIR_ENV = "PEDALREPRO_DATA_DIR"


def has_real_subset() -> bool:
    """Whether the quick workflow's data folder holds the public subset's complete run 3045."""
    import os

    folder = os.environ.get(DATA_DIR_ENV)
    return bool(folder) and all((Path(folder) / f"3045_{c}.xlsx").is_file() for c in "XYZ")


#: Report rows from Moore's measured closed-loop spectra (data/registry_spectra.txt), which
#: are "not reproducible here" unless the data folder holds the four .fig files, as in CI.
SPECTRA_ROW_PREFIX = "table_4_2.spectra."


def has_spectra() -> bool:
    """Whether the data folder holds the measured spectra (data/registry_spectra.txt)."""
    import os

    from pedalrepro import paths

    folder = os.environ.get(DATA_DIR_ENV)
    names = [line.split()[0] for line in (paths.DATA / "registry_spectra.txt").read_text()
             .splitlines() if line.strip() and not line.startswith("#")]
    return bool(folder) and bool(names) and all((Path(folder) / n).is_file() for n in names)


def html_of(doc: str, html_root: Path) -> Path:
    return html_root / (str(Path(doc).with_suffix("")) + ".html")


def test_quick_profile_builds_the_book(quick_workflow):
    tail = "\n".join(quick_workflow.log.splitlines()[-60:])
    assert quick_workflow.returncode == 0, f"snakemake failed:\n{tail}"
    html = quick_workflow.results / "book" / "_build" / "html"
    assert (html / "index.html").is_file()
    # every page of the table of contents was rendered
    docs = report.book_pages()
    missing = [d for d in docs if not html_of(d, html).is_file()]
    assert not missing, f"pages in _toc.yml not rendered: {missing}"
    assert len(docs) >= 9  # intro, chapters 2-5, appendices, report, deviations at least
    print(f"\nquick workflow: {quick_workflow.elapsed_s:.0f} s, {len(docs)} pages")


def test_reproduction_report_is_complete(quick_workflow):
    assert quick_workflow.returncode == 0
    path = quick_workflow.results / "tables" / "reproduction_report.csv"
    assert path.is_file()
    raw = pd.read_csv(path)  # default NA parsing: an empty or "nan" cell becomes NaN
    assert list(raw.columns) == list(report.COLUMNS)
    assert len(raw) > 0, "the reproduction report has no rows"
    required = ["item", "section", "published", "tolerance", "status"]
    assert not raw[required].isna().any().any(), raw[raw[required].isna().any(axis=1)]
    df = pd.read_csv(path, dtype=str, keep_default_na=False)
    assert set(df["status"]) <= set(report.STATUSES), set(df["status"]) - set(report.STATUSES)
    # a reproduced value may be absent only where the input is not available here
    no_value = df["reproduced"].str.strip().str.lower().isin(["", "nan", "none"])
    bad = df[no_value & (df["status"] != report.NOT_REPRODUCIBLE)]
    assert bad.empty, f"rows without a reproduced value:\n{bad}"
    counts = report.summary(df)
    assert sum(counts.values()) == len(df)
    print(f"\nreport: {len(df)} rows, {counts}")


def test_report_statuses_are_pinned(quick_workflow):
    """Every row's status equals the one pinned for the quick profile in tests/expected_status.csv
    (rows added or removed count as changes): a status cannot change unnoticed."""
    assert quick_workflow.returncode == 0
    path = quick_workflow.results / "tables" / "reproduction_report.csv"
    rep = pd.read_csv(path, dtype=str, keep_default_na=False)
    expected = report.expected_status()
    if not has_real_subset():
        if required(REAL):  # CI: the six REAL rows must be there, never dropped
            pytest.fail(f"${DATA_DIR_ENV} does not hold the public subset ({REAL}=1): the "
                        f"{REAL_ROW_PREFIX}* rows pinned in {report.EXPECTED_STATUS_FILE} "
                        "cannot be checked")
        # The REAL rows (run 3045 vs Table 4.1, claims table_4_1.real_run_*) exist only when the
        # data folder holds the public subset, as in CI (.ci/run copies ../shared into
        # PEDALREPRO_DATA_DIR), where they are pinned like every other row. Without the subset
        # they must be absent, and only those may be missing.
        real = expected["id"].str.startswith(REAL_ROW_PREFIX)
        assert not rep["id"].str.startswith(REAL_ROW_PREFIX).any(), (
            f"{REAL_ROW_PREFIX}* rows without the public subset in ${DATA_DIR_ENV}")
        expected = expected[~real]
    if not has_spectra():
        if required(REAL):
            pytest.fail(f"${DATA_DIR_ENV} does not hold the measured spectra ({REAL}=1)")
        # the CF rows from Moore's spectra are "not reproducible here" without the files
        expected = expected[~expected["id"].str.startswith(SPECTRA_ROW_PREFIX)]
        rep = rep[~rep["id"].str.startswith(SPECTRA_ROW_PREFIX)]
    changes = report.status_changes(rep, expected, "quick")
    assert changes.empty, (
        f"{len(changes)} report statuses differ from {report.EXPECTED_STATUS_FILE} (quick "
        f"profile; '' = no such row):\n{changes.to_string(index=False)}\n"
        "If the change is intended, record it with\n"
        f"    pedalrepro report-status --profile quick --update {path}\n"
        "and commit tests/expected_status.csv in the same commit as the change, giving the "
        "reason for every changed status in the commit message.")


def test_figs_4_10_4_11_cf_points_equal_the_closed_loop_comparison(quick_workflow):
    """Figs 4.10-4.11's CF points from the measured spectra (the figure data of rule
    validation_figure_data) are the closed-loop comparison's CF spectra rows
    (closed_loop_validation.csv, Table 4.2's CF column): the same measured amplitude and the
    same open-loop model, to the table's 6 significant digits (5e-6 relative); a build without
    the spectra has neither."""
    assert quick_workflow.returncode == 0
    res = quick_workflow.results
    with np.load(res / "intermediate" / "figures" / "validation.npz") as d:
        fig = {k: d[k] for k in d.files if k.startswith("spectra_")}
    table = pd.read_csv(res / "tables" / "closed_loop_validation.csv")
    rows = table[table.source.str.startswith("CF spectra")]
    if not has_spectra():
        if required(REAL):
            pytest.fail(f"${DATA_DIR_ENV} does not hold the measured spectra ({REAL}=1)")
        assert not fig and rows.empty
        return
    assert len(fig["spectra_speed_kmh"]) == 9  # 2, 3, 4, 5, 10, 15, 20, 25, 30 km/h
    for q in ("roll", "steer"):
        sub = rows[rows.quantity == q].sort_values("speed_kmh")
        np.testing.assert_allclose(sub.speed_kmh, fig["spectra_speed_kmh"], rtol=5e-6)
        np.testing.assert_allclose(sub.measured_rad, fig[f"spectra_{q}_measured_rad"],
                                   rtol=5e-6)
        np.testing.assert_allclose(sub.open_loop_rad, fig[f"spectra_{q}_model_rad"],
                                   rtol=5e-6)


def test_book_is_offline(quick_workflow):
    """No page references a script, style, font or image on another host; MathJax is local."""
    assert quick_workflow.returncode == 0
    html_root = quick_workflow.results / "book" / "_build" / "html"
    pages = sorted(html_root.rglob("*.html"))
    assert pages
    external = re.compile(
        r"""<(script|link|img|iframe|source)\b[^>]*\b(src|href)=["'](https?:)?//""", re.IGNORECASE)
    offenders = {str(p.relative_to(html_root)): m.group(0)
                 for p in pages for m in [external.search(p.read_text(errors="replace"))] if m}
    assert not offenders, offenders
    css_url = re.compile(r"url\(\s*['\"]?(https?:)?//", re.IGNORECASE)
    css_bad = [str(p) for p in html_root.rglob("*.css") if css_url.search(p.read_text())]
    assert not css_bad, css_bad
    mathjax = html_root / "_static" / "mathjax" / "tex-mml-chtml.js"
    assert mathjax.is_file() and mathjax.stat().st_size > 500_000
    assert (mathjax.parent / "output" / "chtml" / "fonts" / "woff-v2").is_dir()
    appendices = (html_root / "appendices.html").read_text()
    assert '_static/mathjax/tex-mml-chtml.js' in appendices


def test_book_shows_no_machine_paths(quick_workflow):
    """No page prints where this machine keeps the results, the repository or the home folder
    (issue 13: a chapter printed a local absolute path)."""
    import os

    assert quick_workflow.returncode == 0
    html_root = quick_workflow.results / "book" / "_build" / "html"
    needles = {str(quick_workflow.results.resolve()), str(paths.ROOT.resolve()),
               os.path.expanduser("~")}
    found = {str(p.relative_to(html_root)): n for p in html_root.rglob("*.html")
             if "_static" not in p.parts
             for n in needles if n and n != "/" and n in p.read_text(errors="replace")}
    assert not found, found


def test_snakemake_lint_clean_apart_from_environment_notice():
    proc = subprocess.run(
        [sys.executable, "-m", "snakemake", "--lint", "--configfile", "config/quick.yaml",
         "--config", "results_dir=results/pytest_lint"],
        cwd=paths.ROOT, capture_output=True, text=True,
    )
    out = proc.stdout + proc.stderr
    lints = re.findall(r"^\s+\* (.+?):?\s*$", out, flags=re.MULTILINE)
    other = [line for line in lints if line.rstrip(":") != ALLOWED_LINT.rstrip(":")]
    assert not other, f"snakemake --lint:\n{out}"
    assert "Traceback" not in out and "Error" not in out.split("Lints for")[0], out


def test_benchmark_files_give_the_longest_first_priorities(quick_workflow, tmp_path):
    """``paths.last_runtime_s`` (the rules' ``longest_first`` priority) reads Snakemake's own
    benchmark files: every NT/NP sweep job of the quick run has one with a wall time between 0
    and the whole run's; a missing, empty or garbled file gives None (the rule's fallback)."""
    assert quick_workflow.returncode == 0
    files = sorted((quick_workflow.results / "benchmarks").glob("nonlinear_time_chunk_N*_*_0.tsv"))
    assert len(files) == 8  # NT and NP of HS, CF, HR, CR, 1 chunk (config/quick.yaml)
    seconds = [paths.last_runtime_s(f) for f in files]
    assert all(s is not None and 0 < s < quick_workflow.elapsed_s for s in seconds), seconds
    garbled = tmp_path / "garbled.tsv"
    for text in ("", "s\th:m:s\n", "s\th:m:s\nabc\t0:00:01\n", "-1\t0:00:00\n"):
        garbled.write_text(text)
        assert paths.last_runtime_s(garbled) is None, text
    assert paths.last_runtime_s(tmp_path / "missing.tsv") is None
