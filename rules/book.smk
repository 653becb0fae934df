# The jupyter-book, in two steps. Each notebook (notebooks/*.ipynb, which read results/ and call
# pedalrepro.figures) is executed in its own job (rule book_notebook, kernel in notebooks/, as
# jupyter-book executed it; a failing cell or a stderr output fails that job, the traceback in
# its log), so that -j2 runs two at once. The rule book then renders HTML, strictly (warnings are
# errors), from a staging copy of book/ holding the executed notebooks, which it does not execute
# again; it executes only the MyST text notebooks book/*.md (pedalrepro.book.stage_source).

import json

import yaml

BOOK_INDEX = f"{R}/book/_build/html/index.html"


# The configuration in effect, for the notebooks (pedalrepro.config.results_config): its params are
# the whole config, so any change rewrites it and rebuilds the book, and nothing else.
rule write_config:
    input:
        code=code_inputs("scripts/write_config.py"),
    output:
        CONFIG_COPY,
    params:
        # canonical (sorted keys): the same values in another key order are no change
        config=json.dumps(config, sort_keys=True),
    log:
        logfile("write_config"),
    benchmark:
        bench("write_config")
    message:
        "The configuration in effect -> {output} (notebooks read this copy)"
    script:
        "scripts/write_config.py"


MATHJAX = "book/_mathjax/mathjax/tex-mml-chtml.js"


rule mathjax:
    input:
        "package.json",
        "package-lock.json",
    output:
        MATHJAX,
    log:
        logfile("mathjax"),
    benchmark:
        bench("mathjax")
    message:
        "Copying the vendored MathJax 3 (node_modules, from `npm ci`) into book/_mathjax"
    shell:
        "(test -f node_modules/mathjax/es5/tex-mml-chtml.js"
        " || {{ echo 'MathJax is missing: run npm ci (bash scripts/setup.sh)'; exit 1; }}"
        " && mkdir -p book/_mathjax/mathjax"
        " && cp -r node_modules/mathjax/es5/output book/_mathjax/mathjax/"
        " && cp node_modules/mathjax/es5/tex-mml-chtml.js {output}) > {log} 2>&1"


#: The book's notebooks (by stem), each executed by rule book_notebook.
BOOK_NOTEBOOKS = sorted(p.stem for p in Path("notebooks").glob("*.ipynb"))
#: The executed notebooks, outputs kept; the rule book renders them as they are.
EXECUTED_NOTEBOOK = f"{R}/book/executed/notebooks/{{stem}}.ipynb"
# The code every notebook job runs besides its notebook's own closure: the rule script and the
# drawing modules, which figures.draw(id) imports by the registry's name (no import statement
# for code_inputs to follow), with their closures
from pedalrepro.figures import registry as _registry

BOOK_NOTEBOOK_CODE = set(code_inputs("scripts/book_notebook.py")) | set(
    code_inputs(*sorted({f"../{s}" for g in _registry.groups() for s in _registry.code_sources(g)}))
)
# book/_config.yml's execute section: the notebooks' jobs use its timeout and stderr setting
with open("book/_config.yml") as _fh:
    BOOK_EXECUTE = yaml.safe_load(_fh)["execute"]


rule book_notebook:
    input:
        BOOK_INPUTS,
        CONFIG_COPY,
        "book/_config.yml",
        notebook="notebooks/{stem}.ipynb",
        # the notebook, every pedalrepro module its code cells import, and the data files those
        # modules declare (pedalrepro.dependencies); the script and the drawing modules
        code=lambda wildcards: sorted(
            BOOK_NOTEBOOK_CODE | set(code_inputs(f"../notebooks/{wildcards.stem}.ipynb"))
        ),
    output:
        EXECUTED_NOTEBOOK,
    params:
        cwd=str(ROOT_DIR / "notebooks"),  # where jupyter-book executed it: paths, hrefs unchanged
        timeout=BOOK_EXECUTE["timeout"],
        stderr_output=BOOK_EXECUTE["stderr_output"],
    wildcard_constraints:
        stem="|".join(BOOK_NOTEBOOKS),
    # the longest notebooks first, so two jobs end together (job times: results/benchmarks)
    priority: longest_first("book_notebook_{stem}")
    log:
        logfile("book_notebook_{stem}"),
    benchmark:
        bench("book_notebook_{stem}")
    message:
        "Executing notebooks/{wildcards.stem}.ipynb for the book -> {output} (log: {log})"
    script:
        "scripts/book_notebook.py"


rule book:
    input:
        BOOK_INPUTS,
        CONFIG_COPY,
        MATHJAX,
        "book/_toc.yml",
        # the MyST text notebooks among them are executed in this build
        sorted(str(p) for p in Path("book").glob("*.md")),
        # book/ (its folder) is copied with the executed notebooks into the staging folder
        config="book/_config.yml",
        notebooks=expand(EXECUTED_NOTEBOOK, stem=BOOK_NOTEBOOKS),
        # the API reference page (book/api.md) shows every module's docstrings (autodoc), and
        # the book/*.md pages import the package
        code=sorted(
            set(code_inputs("scripts/book.py"))
            | {str(p) for p in Path("src/pedalrepro").rglob("*.py")}
        ),
    output:
        BOOK_INDEX,
    params:
        out=lambda wildcards, output: str(Path(output[0]).parents[2]),  # <R>/book
        # the staging source folder (pedalrepro.book.stage_source): <R>/book/src
        src=lambda wildcards, output: str(Path(output[0]).parents[2] / "src"),
        figures=lambda wildcards: str(_paths.figures(R)),
        tables=lambda wildcards: str(_paths.tables(R)),
    log:
        logfile("book"),
    benchmark:
        bench("book")
    message:
        "Building the jupyter-book (strict) into {params.out}/_build/html (log: {log})"
    # Every figure in the book links its full-size PNG and its PDF, served from
    # _build/html/figures/ (pedalrepro.figures.BOOK_FIGURES_HREF), every table its CSV from
    # _build/html/tables/ (BOOK_TABLES_HREF); the script copies results/figures and tables there.
    script:
        "scripts/book.py"
