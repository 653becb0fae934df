# Rules that stay on the machine running Snakemake when jobs go to a cluster (profiles/slurm):
# figures, reports, joins and the book take seconds each (or need the network or the source
# tree), so one SLURM job apiece would only add queue time and flood the scheduler. Selected by
# name so that rules added later follow the same convention; included last in the Snakefile.
# With the local executor (snakemake -j2) localrules changes nothing.

CLUSTER_LOCAL_RULES = sorted(
    r.name
    for r in workflow.rules
    if "figure" in r.name  # section2_figure, linear_figures_*, nonlinear_figure, ...
    or r.name.endswith("_report")  # report rows of each part and the joined report
    or r.name
    in {
        "all",
        "book",  # jupyter-book renders the book (source tree)
        "book_notebook",  # executes a notebook against results/ in notebooks/ (source tree)
        "mathjax",  # copies node_modules into book/ (source tree)
        "write_config",  # the config copy the notebooks read (rules/book.smk)
        "nonlinear_codegen",  # cat of the four variant stamps
        "nonlinear_time",  # joins the sweep chunks (reads only, under 1 s)
        "periodic_map_subgrid",  # cuts the thesis-grid map out of the finer one (reads only)
        "mocap_runs",  # downloads the treadmill data (compute nodes often have no network)
        "section2_table_d_1",
        "section2_numbers",
        "linear_table_4_1",
        "validation_tables",
        "closed_loop_lean",  # the lean rider's table (seconds)
    }
)

# What the `localrules:` directive compiles to; the directive itself takes literal names only.
workflow.localrules(*CLUSTER_LOCAL_RULES)
