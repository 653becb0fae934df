"""The book's plumbing: id-tagged figures, the figure-id list, report helpers, strict build."""

from __future__ import annotations

import base64
import json
import os
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import nbformat
import numpy as np
import pandas as pd
import pytest
import yaml
from required import BOOK, skip_unless_required

from pedalrepro import figures, paths, report


def _png_size(png: bytes) -> tuple[int, int]:
    """Width and height from a PNG's IHDR chunk (independent of matplotlib)."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", png[16:24])


def _captured_show(monkeypatch, *args, **kwargs) -> dict:
    shown = []
    monkeypatch.setattr("IPython.display.display", lambda obj, raw=False: shown.append(obj))
    figures.show(*args, **kwargs)
    assert len(shown) == 1
    return shown[0]


def test_show_figure_carries_its_id_and_the_image(monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.setenv("PEDALREPRO_RESULTS", "/nonexistent")  # no rule file: no full-size link
    fig = plt.figure(figsize=(2.0, 1.0), dpi=50)
    bundle = _captured_show(monkeypatch, fig, "fig_3_10", "Roll <amplitude> & steer.")
    with figures.style():  # rendered in the project's style: dpi and the tight bbox's pad
        dpi = matplotlib.rcParams["savefig.dpi"]
        pad = matplotlib.rcParams["savefig.pad_inches"]
    assert not plt.fignum_exists(fig.number)  # closed: the inline backend will not show it twice
    html = bundle["text/html"]
    assert 'data-figure-id="fig_3_10"' in html and 'id="pedalrepro-fig_3_10"' in html
    assert 'alt="fig_3_10: Figure 3.10"' in html
    assert "Figure 3.10 of the thesis" in html
    assert "Roll &lt;amplitude&gt; &amp; steer." in html  # caption escaped
    data = re.search(r'src="data:image/png;base64,([^"]+)"', html).group(1)
    png = base64.b64decode(data)
    width, height = _png_size(png)
    assert abs(width - (2.0 + 2 * pad) * dpi) <= 1 and abs(height - (1.0 + 2 * pad) * dpi) <= 1
    assert "href" not in html
    assert base64.b64decode(bundle["image/png"]) == png


def test_show_table_and_saved_files(monkeypatch, tmp_path):
    df = pd.DataFrame({"case": ["hybrid_O"], "amplitude_m": [0.0682594766]})
    html = _captured_show(monkeypatch, df, "table_d_1")["text/html"]
    assert 'data-figure-id="table_d_1"' in html and "Table D.1 of the thesis" in html
    assert "0.0682595" in html and "<table" in html
    # None -> the pipeline's own results/tables/<id>.csv
    monkeypatch.setenv("PEDALREPRO_RESULTS", str(tmp_path))
    with pytest.raises(FileNotFoundError, match="table_4_1"):
        figures.show(None, "table_4_1")
    paths.table("table_4_1").parent.mkdir(parents=True)
    df.to_csv(paths.table("table_4_1"), index=False)
    html = _captured_show(monkeypatch, None, "table_4_1")["text/html"]
    assert 'data-figure-id="table_4_1"' in html and "hybrid_O" in html
    with pytest.raises(ValueError, match="figure id"):
        figures.show(df, "")
    with pytest.raises(ValueError, match="not fig_"):
        figures.show(df, "figure2")


def test_figure_id_list_follows_the_thesis():
    ids = report.figure_ids()
    # the checklist: Section 2 (8), Section 3 (50), Section 4 (12) result figures and tables
    assert len(ids) == 70
    assert ids["id"].is_unique
    assert ids.groupby("chapter").size().to_dict() == {"2": 8, "3": 50, "4": 12}
    assert all(t == figures.thesis_label(i) for i, t in zip(ids["id"], ids["thesis"], strict=True))
    assert (ids["id"].str.startswith("table_").sum(), len(ids)) == (3, 70)
    # thesis order within each chapter: main-text numbers ascend
    main = ids[ids["id"].str.fullmatch(r"fig_\d_\d+")]
    for _, grp in main.groupby("chapter"):
        numbers = [int(i.rsplit("_", 1)[1]) for i in grp["id"]]
        assert numbers == sorted(numbers)


def test_figure_coverage_counts_result_files(monkeypatch, tmp_path):
    monkeypatch.setenv("PEDALREPRO_RESULTS", str(tmp_path))
    assert report.figure_coverage()["present"].sum() == 0
    for fid in ("fig_2_3", "fig_g_7"):
        paths.figure(fid).parent.mkdir(parents=True, exist_ok=True)
        paths.figure(fid).write_bytes(b"png")
    paths.table("table_d_1").parent.mkdir(parents=True, exist_ok=True)
    paths.table("table_d_1").write_text("x\n1\n")
    cov = report.figure_coverage()
    assert sorted(cov.loc[cov["present"], "id"]) == ["fig_2_3", "fig_g_7", "table_d_1"]
    # another results folder, named: tables and figures both looked up there (the registry's
    # coverage(root) once counted tables in the default folder only)
    monkeypatch.setenv("PEDALREPRO_RESULTS", str(tmp_path / "elsewhere"))
    assert report.figure_coverage()["present"].sum() == 0
    cov = report.figure_coverage(tmp_path)
    assert sorted(cov.loc[cov["present"], "id"]) == ["fig_2_3", "fig_g_7", "table_d_1"]


@pytest.mark.parametrize("section, chapter", [
    ("2.2.1", "2"), ("Sec 2.2.2", "2"), ("3.2.4 1a", "3"), ("Fig 3.12", "3"),
    ("3.2.1 / Fig 3.9", "3"), ("Table 4.1", "4"), ("4.3", "4"), ("5", "5"),
    ("Appendix B", "appendix"), ("Table D.1", "appendix"), ("Fig G.7", "appendix"),
    ("B.3", "appendix"), ("Hybrid", "other"), ("", "other"),
])
def test_report_rows_grouped_by_thesis_chapter(section, chapter):
    assert report.thesis_chapter(section) == chapter


def test_report_helpers(tmp_path):
    empty = report.combine([], tmp_path / "r.csv")
    assert list(empty.columns) == list(report.COLUMNS) and empty.empty
    rows = [report.Row("NRMSD <vertical> COM", "2.2.1", "3.6", "3.57", "abs 0.05",
                       report.REPRODUCED, id="a"),
            report.Row("Table 4.1 roll measured", "Table 4.1", "0.011", "", "n/a",
                       report.NOT_REPRODUCIBLE, "treadmill data not available", id="b")]
    df = report.write_rows(rows, tmp_path / "part.csv")
    assert len(report.select(df, "2.2", "vertical")) == 1
    assert len(report.select(df, "2.2", "horizontal")) == 0
    assert len(report.select(df, "Table 4")) == 1
    html = report.rows_html(df)
    # header, two rows, and row b's note on a full-width line of its own (never cut off)
    assert "NRMSD &lt;vertical&gt; COM" in html and html.count("<tr") == 4
    assert 'id="report-a"' in html and 'id="report-b"' in html
    assert html.count('colspan="6"') == 1 and "treadmill data not available" in html
    assert "No row" in report.rows_html(df.iloc[:0], empty="No row")
    # other pages link the rows instead of re-printing them: counts, then only the findings
    links = report.links_html(df)
    assert "Report rows (2)" in links and "<td" not in links
    assert links.count("<a href=") == 1
    assert f'href="{report.REPORT_PAGE}#report-b"' in links


def test_book_pages_are_in_the_toc():
    toc = yaml.safe_load((paths.BOOK / "_toc.yml").read_text())
    text = json.dumps(toc)
    for doc in ("intro", "notebooks/02_pedalling_disturbance", "notebooks/03_open_loop_response",
                "notebooks/04_validation", "conclusions", "appendices",
                "notebooks/reproduction_report", "deviations"):
        assert f'"{doc}"' in text, doc
    # the order of the thesis: 2 < 3 < 4 < 5 < appendices < report < deviations
    order = [text.index(f'"{d}"') for d in ("notebooks/02_pedalling_disturbance",
             "notebooks/03_open_loop_response", "notebooks/04_validation", "conclusions",
             "appendices", "notebooks/reproduction_report", "deviations")]
    assert order == sorted(order)


def _page_title(doc: str) -> str:
    """The first ``# `` heading of a book page (notebook or MyST markdown)."""
    path = paths.ROOT / "book" / (doc + ".md")
    if doc.startswith("notebooks/"):
        nb = json.loads((paths.ROOT / (doc + ".ipynb")).read_text())
        text = "\n".join("".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown")
    else:
        text = path.read_text()
    return next(line[2:].strip() for line in text.splitlines() if line.startswith("# "))


def test_book_section_numbers_are_unique():
    """No two pages carry the same leading section number (issue 13: two sections were 3.3)."""
    titles = {doc: _page_title(doc) for doc in report.book_pages()}
    numbers = {}
    for doc, title in titles.items():
        m = re.match(r"([0-9]+(?:\.[0-9]+)*)\s", title)
        if m:
            numbers.setdefault(m.group(1), []).append(doc)
    assert len(numbers) >= 6, titles  # 2, 3, 3.1-3.4, 4, 5
    repeated = {n: docs for n, docs in numbers.items() if len(docs) > 1}
    assert not repeated, repeated


#: Pages whose code is their content (worked examples on the API): shown, not folded.
CODE_PAGES = ("07_own_analysis.ipynb",)


def test_notebook_code_is_folded_away():
    """Every code cell of a book notebook is hidden (``hide-input``: folded, one click shows it)
    or removed: readers see results and text, not loading code (issue 13, part 5)."""
    bare = []
    for nb_path in sorted((paths.ROOT / "notebooks").glob("*.ipynb")):
        if nb_path.name in CODE_PAGES:
            continue
        nb = json.loads(nb_path.read_text())
        for i, cell in enumerate(nb["cells"]):
            tags = cell.get("metadata", {}).get("tags", [])
            if cell["cell_type"] == "code" and not any(
                    t in ("hide-input", "hide-cell", "remove-input", "remove-cell") for t in tags):
                bare.append(f"{nb_path.name} cell {i}")
    assert not bare, bare


def test_api_reference_documents_every_module():
    """The API pages (book/api.md and its group pages book/api_*.md) have one ``automodule`` for
    every public module of the package (a new module must be added to the API reference), and the
    book's Sphinx loads autodoc and napoleon."""
    src = paths.ROOT / "src"
    modules = {".".join(p.relative_to(src).with_suffix("").parts).removesuffix(".__init__")
               for p in (src / "pedalrepro").rglob("*.py")
               if not any(part.startswith("_") and part != "__init__.py" for part in p.parts)
               and p.name != "__main__.py"}
    pages = sorted(paths.BOOK.glob("api*.md"))  # api.md: the index; api_<group>.md: the groups
    assert len(pages) >= 6  # split by module group (issue 25): no 145k-px page
    text = "\n".join(p.read_text() for p in pages)
    listed = re.findall(r"^\.\. automodule:: (\S+)$", text, re.M)
    assert len(listed) == len(set(listed)), "a module documented on two pages"
    documented = set(listed)
    assert len(modules) >= 60
    assert modules == documented, (sorted(modules - documented), sorted(documented - modules))
    # each module's directive: packages show their docstring, modules also their members (once)
    blocks = re.findall(r"^\.\. automodule:: (\S+)\n((?:   :\S+:.*\n)*)", text, re.M)
    packages = {m for m in modules if (src / m.replace(".", "/") / "__init__.py").is_file()}
    options = {m: opts.split() for m, opts in blocks}
    assert all(options[m] == ([] if m in packages else [":members:"]) for m in modules), options
    config = yaml.safe_load((paths.BOOK / "_config.yml").read_text())["sphinx"]["config"]
    assert {"sphinx.ext.autodoc", "sphinx.ext.napoleon"} <= set(config["extensions"])
    toc = json.dumps(yaml.safe_load((paths.BOOK / "_toc.yml").read_text()))
    assert all(f'"{p.stem}"' in toc for p in pages)


def test_deviations_page_covers_every_erratum():
    """Each of the 17 errata items, and the later findings (Table 4.1 rounding boundary, Fig H.6
    caption, example points, steer sign of convertData.m), has its own treatment (keywords)."""
    text = (paths.BOOK / "deviations.md").read_text()
    keywords = ["Eq 2.3", "Crank mass", "Eq 2.2", "B.18-B.23", "Eq 2.13", "3.6 %",
                "dependent on cadence", "About 12 N", "About 2 %", "Seat-tube angle",
                "Fourier conventions", "Eq B.30", "Table ??", "0.77 m", "CR cadences",
                "weave or capsize", "Hip width", "SYNTHETIC", "Model substitutes",
                "rounding-boundary cell", "Figure H.6", "example points", "convertData.m"]
    assert [k for k in keywords if k not in text] == []


def _mini_workflow(tmp_path: Path, cell_source: str) -> subprocess.CompletedProcess:
    """The repository's book rules (rules/book.smk: book_notebook, then book) on a temporary copy
    whose book holds only the introduction and one notebook with ``cell_source``."""
    root = tmp_path / "repo"
    for rel in ("rules/common.smk", "rules/book.smk", "rules/scripts/write_config.py",
                "rules/scripts/book_notebook.py", "rules/scripts/book.py",
                "package.json", "package-lock.json"):
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(paths.ROOT / rel, root / rel)
    # the data files the package declares (the notebook jobs' inputs include the drawing modules')
    shutil.copytree(paths.DATA, root / "data")
    shutil.copytree(paths.CONFIG, root / "config")
    shutil.copytree(paths.ROOT / "src", root / "src",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    (root / "node_modules").symlink_to(paths.ROOT / "node_modules")
    book = root / "book"
    book.mkdir()
    shutil.copy2(paths.BOOK / "_config.yml", book / "_config.yml")
    (book / "intro.md").write_text("# Probe book\n\nMath $x^2$.\n")
    (book / "_toc.yml").write_text("format: jb-book\nroot: intro\nchapters:\n"
                                   "  - file: notebooks/probe\n")
    (root / "notebooks").mkdir()
    (book / "notebooks").symlink_to("../notebooks")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell("# Probe"),
                                         nbformat.v4.new_code_cell(cell_source)])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nbformat.write(nb, root / "notebooks" / "probe.ipynb")
    (root / "Snakefile").write_text(
        'configfile: "config/config.yaml"\n\n\ninclude: "rules/common.smk"\n'
        'include: "rules/book.smk"\n\n\nrule all:\n    input:\n        BOOK_INDEX,\n')
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    return subprocess.run([sys.executable, "-m", "snakemake", "-j1", "--configfile",
                           "config/quick.yaml", "--config", "results_dir=results"],
                          cwd=root, env=env, capture_output=True, text=True)


def test_a_failing_notebook_cell_fails_the_book_rule(tmp_path):
    if not (paths.ROOT / "node_modules" / "mathjax").is_dir():
        skip_unless_required(BOOK, "MathJax not installed (npm ci)")
    good = _mini_workflow(tmp_path / "good", "x = 1 + 1\nx")
    assert good.returncode == 0, good.stdout + good.stderr
    assert (tmp_path / "good/repo/results/book/_build/html/index.html").is_file()
    # the notebook was executed by its own job, and the book rendered it without executing it
    executed = nbformat.read(tmp_path / "good/repo/results/book/executed/notebooks/probe.ipynb",
                             as_version=4)
    assert executed.cells[1].outputs[0]["data"]["text/plain"] == "2"
    book_log = (tmp_path / "good/repo/results/logs/book.log").read_text()
    assert "probe.ipynb: Excluded from execution by pattern" in book_log
    page = (tmp_path / "good/repo/results/book/_build/html/notebooks/probe.html").read_text()
    assert re.search(r'class="output text_plain[^"]*"><div class="highlight"><pre><span></span>2\n',
                     page)
    bad = _mini_workflow(tmp_path / "bad", "raise RuntimeError('deliberately broken cell')")
    assert bad.returncode != 0
    out = bad.stdout + bad.stderr
    # the notebook's job fails, and its message names the notebook and the broken cell
    assert "Error in rule book_notebook" in out
    assert "notebooks/probe.ipynb failed" in out and "deliberately broken cell" in out
    # the failed build leaves no book behind, and the job's log names the cause
    assert not (tmp_path / "bad/repo/results/book/_build/html/index.html").exists()
    assert not (tmp_path / "bad/repo/results/book/executed/notebooks/probe.ipynb").exists()
    log = (tmp_path / "bad/repo/results/logs/book_notebook_probe.log").read_text()
    assert "deliberately broken cell" in log and "probe.ipynb" in log and "Traceback" in log


def test_a_cell_writing_to_stderr_fails_its_notebook(tmp_path):
    """``execute.stderr_output: error`` (book/_config.yml): a cell writing to stderr fails the
    notebook's execution, as it fails myst-nb's rendering; a cell tagged ``remove-stderr`` does
    not."""
    from pedalrepro import book

    def notebook(cell):
        nb = nbformat.v4.new_notebook(cells=[cell])
        nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                     "language": "python"}
        path = tmp_path / "probe.ipynb"
        nbformat.write(nb, path)
        return path

    noisy = nbformat.v4.new_code_cell("import sys\nprint('noisy warning', file=sys.stderr)")
    with pytest.raises(RuntimeError, match="stderr was found in the cell outputs of cell 1"):
        book.execute_notebook(notebook(noisy), tmp_path / "out.ipynb", timeout=60)
    assert not (tmp_path / "out.ipynb").exists()
    noisy.metadata["tags"] = ["remove-stderr"]
    book.execute_notebook(notebook(noisy), tmp_path / "out.ipynb", timeout=60)
    assert (tmp_path / "out.ipynb").is_file()
    with pytest.raises(RuntimeError, match="probe.ipynb: executing the notebook failed"):
        book.execute_notebook(notebook(nbformat.v4.new_code_cell("1 / 0")),
                              tmp_path / "out.ipynb", timeout=60)


def _kernel_texts(source: str) -> list[str]:
    from nbclient import NotebookClient

    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(source)])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    NotebookClient(nb, timeout=60).execute()
    return [next(iter(o["data"].values())) for o in nb.cells[0].outputs]


def test_glued_numpy_scalars_are_plain_numbers():
    """A notebook that asks (``book.setup()``) glues ``3.1536``, not ``np.float64(3.1536)`` (which
    {glue:text} formatting cannot parse: a strict-build failure); importing pedalrepro.figures
    alone changes nothing in IPython (issue 21, part 5)."""
    glue_cell = ("glue('a', np.float64(3.1536), display=False)\n"
                 "glue('b', np.int64(7), display=False)\nnp.float32(0.5)")
    imports = "import numpy as np\nfrom myst_nb import glue\nfrom pedalrepro import figures\n"
    assert _kernel_texts(imports + glue_cell) == [
        "np.float64(3.1536)", "np.int64(7)", "np.float32(0.5)"]
    assert _kernel_texts(imports + "from pedalrepro import book\nbook.setup()\n"
                         + glue_cell) == ["3.1536", "7", "0.5"]


def test_every_glueing_notebook_asks_for_plain_numbers():
    """Each book page that glues calls ``book.setup()`` (the explicit call that replaced the patch
    on import; with ``figure_status=`` on the pages showing thesis figures), before its first
    glue."""
    missing = []
    pages = sorted((paths.ROOT / "notebooks").glob("*.ipynb")) + sorted(paths.BOOK.glob("*.md"))
    for page in pages:
        if page.suffix == ".ipynb":
            nb = json.loads(page.read_text())
            text = "\n".join("".join(c["source"]) for c in nb["cells"]
                             if c["cell_type"] == "code")
        else:
            text = page.read_text()
        if "glue(" in text:
            call = re.search(r"book\.setup\((figure_status=[^\n]*)?\)", text)
            if call is None or call.start() > text.index("glue("):
                missing.append(page.name)
    assert not missing, missing


# --- issue 25: the book reads cleanly (pedalrepro.book) -----------------------------------------
def test_placeholder_problems_find_what_a_reader_must_not_see():
    from pedalrepro import book

    clean = ('<html><head><script>var x = "{a}";</script></head><body><main><p>Run 3045: '
             '<span class="pasted-text">64.73</span> rpm.</p><pre>{"json": 1}</pre>'
             '<code>{name}</code><span class="math">\\(\\frac{a}{b}\\)</span></main></body>'
             "</html>")
    assert book.placeholder_problems(clean) == []
    bad = ('<p>cadence <span class="pasted-text">(no real run in this build)</span> rpm, '
           'GR {lo}-{hi}, value <span class="pasted-text"></span>, '
           '<span class="pasted-text">np.float64(3.1)</span>'
           ', x <span class="pasted-text">nan</span></p>')
    problems = book.placeholder_problems(bad, "p.html")
    assert len(problems) == 6, problems
    assert sum("unfilled template" in p for p in problems) == 2
    assert sum("empty or NaN glued value" in p for p in problems) == 2
    assert any("(no real run in this build)" in p for p in problems)
    assert any("np.float64(" in p for p in problems)


def test_a_paragraph_is_filled_or_one_note(monkeypatch):
    from pedalrepro import book

    shown = []
    monkeypatch.setattr("IPython.display.display", lambda obj, **kw: shown.append(obj))
    text = book.paragraph("Run {run} at {v:.2f} km/h.", {"run": "3045", "v": 25.04},
                          missing="No run.", how="Get it.")
    assert text == "Run 3045 at 25.04 km/h."
    note = book.paragraph("Run {run}.", None, missing="The real run is not here.",
                          how="Put its files in <code>$PEDALREPRO_DATA_DIR</code>.")
    assert "{" not in note and "The real run is not here." in note and "admonition" in note
    assert book.placeholder_problems(note) == []
    assert len(shown) == 2
    with pytest.raises(KeyError, match="'v'"):
        book.fill("Run {run} at {v} km/h.", {"run": "3045"})
    with pytest.raises(KeyError, match="'run'"):
        book.fill("Run {run}.", {"run": ""})


def test_reader_tables_have_units_no_index_and_a_dash_for_missing():
    from pedalrepro import book

    df = pd.DataFrame({"system": ["HR", "CR", "median"], "speed_kmh": [18.1, 20.0, np.nan],
                       "roll_model_rad": [0.0123456789, np.nan, 0.011],
                       "roll_rd_percent": [12.0, 3.0, 7.5]})
    html = book.reader_table(df)
    assert "overflow-x:auto" in html and "<th>speed (km/h)</th>" in html
    assert "<th>roll rd (%)</th>" in html and "<th>roll model (rad)</th>" in html
    assert "NaN" not in html and "nan" not in html and "<td>-</td>" in html
    assert html.count("<tr") == 4  # header + 3 rows, no index column
    assert "<th></th>" not in html
    big = pd.DataFrame(np.arange(60 * 30).reshape(60, 30) / 7.0)
    assert "..." not in book.reader_table(big) and book.reader_table(big).count("<tr") == 61
    wide = book.runs_as_columns(df, ["system", "speed_kmh"])  # Table 4.1 as the thesis: runs
    assert list(wide.columns) == ["quantity", "HR 18.1 km/h", "CR 20 km/h", "median"]
    assert list(wide["quantity"]) == ["roll model (rad)", "roll rd (%)"]
    assert wide.loc[1, "CR 20 km/h"] == 3.0


@pytest.mark.parametrize("column, shown", [
    ("steer_stiffness_n_m_rad", "steer stiffness (N m/rad)"),  # not "n m (rad)"
    ("rule_kPsi_rad_rad", "rule kPsi (rad/rad)"), ("rule_kY_rad_m", "rule kY (rad/m)"),
    ("rule_kPhi_1_s", "rule kPhi (1/s)"), ("max_real_rad_s", "max real (rad/s)"),
    ("roll_rad", "roll (rad)"), ("kPhiDot_s", "kPhiDot (s)")])
def test_headers_read_compound_units(column, shown):
    from pedalrepro import book

    assert book.header(column) == shown


def test_rule_figures_are_linked_as_files_not_inlined(monkeypatch, tmp_path):
    from pedalrepro import book

    monkeypatch.setenv("PEDALREPRO_RESULTS", str(tmp_path))
    png = paths.figure("fig_3_10")
    png.parent.mkdir(parents=True)
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 2_000_000)
    png.with_suffix(".pdf").write_bytes(b"%PDF-")
    html = _captured_show(monkeypatch, None, "fig_3_10", "Roll.")["text/html"]
    assert 'src="../figures/fig_3_10.png"' in html and "base64" not in html
    assert len(html) < 2_000  # the 2 MB image is not in the page
    # a pipeline figure that is not a thesis figure: captioned, linked full size, never bare
    sub = tmp_path / "figures" / "own_bicycle" / "Rigid_Jason_resonance.png"
    sub.parent.mkdir(parents=True)
    sub.write_bytes(b"\x89PNG")
    html = book.file_figure_html(sub, "The resonance map.")
    assert 'data-figure-file="own_bicycle/Rigid_Jason_resonance"' in html
    assert '<a class="pedalrepro-full-size" href="../figures/own_bicycle/' in html
    assert "<figcaption>The resonance map." in html
    with pytest.raises(ValueError, match="caption"):
        book.file_figure_html(sub, " ")
    with pytest.raises(ValueError, match="not under"):
        book.file_figure_html(tmp_path / "elsewhere.png", "x")


@pytest.mark.workflow
def test_the_built_book_shows_no_placeholder(quick_workflow):
    """Every page of the quick build (the CI build, which has no real subset unless its files are
    in the data folder) reads cleanly: no known placeholder, no unfilled ``{field}``, no empty or
    NaN glued value (issue 25, part 1). ``PEDALREPRO_BOOK_HTML`` names another built book (a
    thesis-profile build) to check instead."""
    from pedalrepro import book

    assert quick_workflow.returncode == 0, quick_workflow.log[-3000:]
    root = Path(os.environ.get("PEDALREPRO_BOOK_HTML",
                               quick_workflow.results / "book" / "_build" / "html"))
    pages = [p for p in sorted(root.rglob("*.html"))
             if not p.relative_to(root).parts[0].startswith("_")
             and p.name not in ("genindex.html", "search.html", "py-modindex.html")]
    assert len(pages) >= 15, [p.name for p in pages]
    problems = [q for p in pages for q in book.placeholder_problems(
        p.read_text(encoding="utf-8"), p.relative_to(root).as_posix())]
    assert not problems, "\n".join(problems)
    print(f"\n{len(pages)} pages read cleanly")


# --------------------------------------------------------------------------------------------
# Each figure shows its report status (issue 25, part 6)
# --------------------------------------------------------------------------------------------

def _report_rows(*rows):
    import pandas as pd

    from pedalrepro import report

    return pd.DataFrame([dict(zip(report.COLUMNS, r, strict=True)) for r in rows], dtype=str)


def test_every_claims_figures_resolve_to_registered_figures():
    """Every claim's ``figures`` entries name registered figures or thesis tables once filled
    with a row's fields: each pinned row resolves, and the selector of the RD claims finds the
    one RD map of the row's model and coordinate (Figs 3.32, 3.33, H.1-H.6)."""
    from pedalrepro import report
    from pedalrepro.figures import registry
    from pedalrepro.report import figure_rows

    for rid in report.expected_status()["id"]:
        figure_rows.figures_of(rid)  # raises on an unknown id
    rd = {(registry.spec(f).kwargs["model"], registry.spec(f).kwargs["coord"]): f
          for f in registry.ids() if registry.spec(f).function == "linear.figs_rd_points"}
    assert len(rd) == 8 and rd[("HR", "roll")] == "fig_3_32" and rd[("CF", "roll")] == "fig_3_33"
    for (model, coord), fid in rd.items():
        assert figure_rows.figures_of(f"rd_2b.{model}.{coord}") == [fid]
    assert set(figure_rows.figures_of("rd_1a")) == set(rd.values())
    # the most specific template: the spectra rows belong to their own claim (Table 4.2's CF
    # column from the spectra, whose points Fig 4.11 draws as diamonds), not the thesis runs' one
    spectra = "table_4_2.spectra.roll_rd_median_percent.CF"
    assert figure_rows.match(spectra)[0].id == "table_4_2.spectra.{key}.CF"
    assert figure_rows.figures_of(spectra) == ["table_4_2", "fig_4_11"]
    assert figure_rows.figures_of("table_4_2.roll_rd_median_percent.CF") == ["table_4_2",
                                                                             "fig_4_11"]
    with pytest.raises(ValueError, match="matches no claim"):
        figure_rows.figures_of("no_such_claim.HS")


def test_a_bad_figures_entry_is_refused(tmp_path):
    from pedalrepro.report import claims_module

    base = ("claims:\n- id: x\n  section: '1'\n  item: x\n  wording: 'quoted'\n"
            "  published_text: '1'\n  check: {kind: holds, describe: x}\n")
    bad = tmp_path / "claims.yaml"
    bad.write_text(base + "  figures: fig_3_9\n")
    with pytest.raises(ValueError, match="'figures' must be a list"):
        claims_module.claims(bad)
    bad2 = tmp_path / "claims2.yaml"
    bad2.write_text(base + "  figures: [{model: HS}]\n")
    with pytest.raises(ValueError, match="'figures' must be a list"):
        claims_module.claims(bad2)


def test_a_figure_caption_ends_with_its_report_status(monkeypatch):
    """With ``book.setup(figure_status=...)`` a thesis figure's caption ends with its rows'
    counts per status, each linking its first row on the report page; a thesis figure no row
    checks says so; a figure beyond the thesis without rows says nothing."""
    from pedalrepro import book, report
    from pedalrepro.report import figure_rows

    rows = _report_rows(
        ("hs_weave_frequency", "HS weave", "3.2.1", "1", "1", "abs 0.1", "reproduced", ""),
        ("cf_weave_stable_speed", "CF", "3.2.1", "1", "2", "abs 0.1", "differs", "why"),
        ("self_stable_range_exists", "3", "3.2.1", "x", "x", "", "reproduced", ""))
    status = figure_rows.caption_status(rows)
    line = status("fig_3_9")
    assert 'class="pedalrepro-status"' in line and "report rows (3)" in line
    assert f'href="reproduction_report.html#{report.anchor("hs_weave_frequency")}">2 ' in line
    assert f'#{report.anchor("cf_weave_stable_speed")}">1 ' in line and "differs" in line
    assert figure_rows.BY_EYE in status("fig_3_10")
    assert status("periodic_continuation") == ""
    try:
        book.setup(figure_status=status)
        html = book.figure_html("fig_3_9", src="figures/fig_3_9.png")
    finally:
        book.setup()
    assert html.index("report rows (3)") > html.index("<figcaption>")
    assert "pedalrepro-status" not in book.figure_html("fig_3_9", src="figures/fig_3_9.png")


@pytest.mark.workflow
def test_every_thesis_figure_in_the_built_book_shows_its_report_status(quick_workflow):
    """Each ``<figure data-figure-id>`` of a thesis figure or table on the built pages carries a
    status line, and the counts it gives are those of the build's report (Fig 3.9 and Table D.1
    checked against the report CSV)."""
    import pandas as pd

    from pedalrepro import book
    from pedalrepro.report import figure_rows

    assert quick_workflow.returncode == 0, quick_workflow.log[-3000:]
    root = quick_workflow.results / "book" / "_build" / "html"
    rep = pd.read_csv(quick_workflow.results / "tables" / "reproduction_report.csv", dtype=str,
                      keep_default_na=False)
    table = figure_rows.by_figure(rep)
    shown = {}
    for page in sorted((root / "notebooks").glob("*.html")):
        text = page.read_text(encoding="utf-8")
        for m in re.finditer(r'<figure class="pedalrepro-figure" id="[^"]*" '
                             r'data-figure-id="([^"]+)">(.*?)</figure>', text, re.S):
            shown.setdefault(m.group(1), m.group(2))
    thesis = {f for f in shown if book.thesis_label(f) != book.BEYOND_THESIS}
    assert len(thesis) >= 60, sorted(shown)
    missing = sorted(f for f in thesis if "pedalrepro-status" not in shown[f])
    assert not missing, f"figures without a report status: {missing}"
    for fid in ("fig_3_9", "table_d_1"):
        assert f"report rows ({len(table[fid])})" in shown[fid], shown[fid][-600:]

