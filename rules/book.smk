# The jupyter-book: executes notebooks/ (which read results/ and call pedalrepro.figures) and
# renders HTML, strictly (warnings are errors; a failing cell fails the build).

BOOK_INDEX = f"{R}/book/_build/html/index.html"


rule book:
    input:
        BOOK_INPUTS,
        "book/_config.yml",
        "book/_toc.yml",
        sorted(str(p) for p in Path("book").glob("*.md")),
        sorted(str(p) for p in Path("notebooks").glob("*.ipynb")),
        pkg("report"),
        sorted(str(p) for p in Path(PKG, "figures").glob("*.py")),
    output:
        BOOK_INDEX,
    log:
        logfile("book"),
    message:
        "Building the jupyter-book (strict) into {R}/book/_build/html"
    shell:
        "jupyter-book build --all -W -n --keep-going book/ --path-output {R}/book > {log} 2>&1"
