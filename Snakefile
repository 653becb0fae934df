# pedalrepro: rebuild every figure and table of the thesis and render the book.
#   snakemake -j2                                   # thesis-size grids -> results/
#   snakemake -j2 --configfile config/quick.yaml    # coarse grids (CI) -> results/quick/
# Physics lives in src/pedalrepro; rules only orchestrate (one file per result family).
from snakemake.utils import min_version

min_version("9.0")


configfile: "config/config.yaml"


include: "rules/common.smk"
include: "rules/section2.smk"
include: "rules/linear.smk"
include: "rules/nonlinear.smk"
include: "rules/periodic.smk"
include: "rules/mocap.smk"
include: "rules/closed_loop.smk"
include: "rules/own_bicycle.smk"
include: "rules/figures.smk"
include: "rules/report.smk"
include: "rules/book.smk"
include: "rules/cluster.smk"  # last: localrules for profiles/slurm


rule all:
    default_target: True
    input:
        BOOK_INDEX,
