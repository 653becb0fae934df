# The jupyter-book: executes notebooks/ (which read results/ and call pedalrepro.figures) and
# renders HTML, strictly (warnings are errors; a failing cell fails the build: jupyter-book exits 1
# with --keep-going once all pages are tried, and the shell rule fails with it).

import json

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


rule book:
    input:
        BOOK_INPUTS,
        CONFIG_COPY,
        MATHJAX,
        "book/_config.yml",
        "book/_toc.yml",
        sorted(str(p) for p in Path("book").glob("*.md")),
        # the notebooks, every pedalrepro module their code cells import, and the data files
        # those modules declare (pedalrepro.dependencies)
        code_inputs(*sorted(f"../{p}" for p in Path("notebooks").glob("*.ipynb"))),
        # the API reference page (book/api.md) shows every module's docstrings (autodoc)
        sorted(str(p) for p in Path("src/pedalrepro").rglob("*.py")),
    output:
        BOOK_INDEX,
    params:
        out=lambda wildcards, output: str(Path(output[0]).parents[2]),  # <R>/book
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
    # _build/html/tables/ (BOOK_TABLES_HREF); the page Downloads lists them all.
    shell:
        "jupyter-book build --all -W -n --keep-going book/ --path-output {params.out} > {log} 2>&1"
        " || {{ tail -n 40 {log} >&2; exit 1; }}"
        " && mkdir -p {params.out}/_build/html/figures {params.out}/_build/html/tables"
        " && {{ test ! -d {params.figures}"
        " || cp -r {params.figures}/. {params.out}/_build/html/figures/ ; }}"
        " && {{ test ! -d {params.tables}"
        " || cp -r {params.tables}/. {params.out}/_build/html/tables/ ; }}"
