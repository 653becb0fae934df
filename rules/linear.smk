# Rules of the linear part (thesis Sec 3, linear methods; see rules/common.smk for helpers):
# eigen analysis, particular solution (PS), time solutions (LA analytic, LN numerical), RD maps,
# Table 4.1 model columns and the report part (the figures: rules/figures.smk).

LINEAR_MODELS = list(config["linear"]["models"])
# Time solutions and RD maps: the four thesis models (the benchmark has PS and eigen figures only).
LINEAR_TIME_MODELS = [m for m in LINEAR_MODELS if m != "benchmark"]
# Time-solution methods drawn in fig_3_10 .. fig_3_33, fig_g_*, fig_h_*. rules/nonlinear.smk
# (included after this file) extends it with "NT", "NP"; inputs read it lazily.
TIME_METHODS = ["LA", "LN"]


rule linear_eigen:
    input:
        code=pkg("linear"),
        appendix_b="data/parameters/appendix_b.yaml",
        benchmark="data/parameters/benchmark.yaml",
    output:
        table=table("eigen_summary"),
        sweeps=expand(interm("eigen/{model}.npz"), model=LINEAR_MODELS),
    params:
        models=LINEAR_MODELS,
    log:
        logfile("linear_eigen"),
    message:
        "Eigenvalues vs speed, weave/capsize speeds and self-stable ranges of {params.models}"
    script:
        "scripts/linear_eigen.py"


rule linear_ps:
    input:
        code=pkg("linear", "response", "momentum", "disturbance", "legs"),
        parameters=["data/parameters/appendix_b.yaml", "data/parameters/legs.yaml"],
    output:
        npz=expand(interm("ps/{model}.npz"), model=LINEAR_MODELS),
    params:
        models=LINEAR_MODELS,
    threads: 1
    log:
        logfile("linear_ps"),
    benchmark:
        bench("linear_ps")
    message:
        "Particular solution of {params.models} on the PS grid (harmonics w, 3w, 5w)"
    script:
        "scripts/linear_ps.py"


# LA is exact and vectorised (seconds per model on the thesis grid): one job for all models.
rule linear_time_la:
    input:
        code=pkg("linear", "response", "spectral", "evaluation", "gears", "disturbance", "legs"),
        parameters=["data/parameters/appendix_b.yaml", "data/parameters/legs.yaml"],
    output:
        npz=expand(interm("time/LA_{model}.npz"), model=LINEAR_TIME_MODELS),
    params:
        method="LA",
        models=LINEAR_TIME_MODELS,
    threads: 1
    log:
        logfile("linear_time_LA"),
    benchmark:
        bench("linear_time_LA")
    message:
        "Analytic time solutions (LA) of {params.models} on the time grid"
    script:
        "scripts/linear_time.py"


# LN integrates every run (minutes per model on the thesis grid): one job per model.
rule linear_time_ln:
    input:
        code=pkg("linear", "response", "spectral", "evaluation", "gears", "disturbance", "legs"),
        parameters=["data/parameters/appendix_b.yaml", "data/parameters/legs.yaml"],
    output:
        npz=interm("time/LN_{model}.npz"),
    params:
        method="LN",
        models=lambda wc: [wc.model],
    wildcard_constraints:
        model="|".join(LINEAR_TIME_MODELS),
    threads: 1
    log:
        logfile("linear_time_LN_{model}"),
    benchmark:
        bench("linear_time_LN_{model}")
    message:
        "Numerical time solutions (LN) of model {wildcards.model} on the time grid"
    script:
        "scripts/linear_time.py"


rule linear_rd:
    input:
        code=pkg("linear", "response", "evaluation", "gears", "disturbance", "legs"),
        ps=expand(interm("ps/{model}.npz"), model=LINEAR_TIME_MODELS),
        la=expand(interm("time/LA_{model}.npz"), model=LINEAR_TIME_MODELS),
        ln=expand(interm("time/LN_{model}.npz"), model=LINEAR_TIME_MODELS),
    output:
        maps=expand(interm("rd/{model}.npz"), model=LINEAR_TIME_MODELS),
        pairs=interm("rd/pairs.npz"),
        table=table("rd_summary"),
    params:
        models=LINEAR_TIME_MODELS,
    log:
        logfile("linear_rd"),
    message:
        "Relative-difference maps of evaluation points 1c, 2b, 3a, 3b, 4, 5, 6 (Eq 3.26)"
    script:
        "scripts/linear_rd.py"


rule linear_table_4_1:
    input:
        code=pkg("linear", "response", "disturbance", "legs"),
        runs="data/parameters/validation_runs.yaml",
        parameters=["data/parameters/appendix_b.yaml", "data/parameters/legs.yaml"],
    output:
        table("table_4_1_model"),
    log:
        logfile("linear_table_4_1"),
    message:
        "Table 4.1 model columns: particular solution at the seven hands-free runs"
    script:
        "scripts/linear_table_4_1.py"


rule linear_report:
    input:
        code=pkg("report", "linear", "response", "evaluation", "gears", "disturbance", "legs",
                 "figdata", "momentum"),
        eigen=table("eigen_summary"),
        rd=table("rd_summary"),
        table_4_1=table("table_4_1_model"),
        ps=expand(interm("ps/{model}.npz"), model=LINEAR_MODELS),
        published=["data/published/thesis_values.yaml", "data/published/meijaard2007.yaml"],
    output:
        f"{R}/tables/report/linear.csv",
    params:
        models=LINEAR_MODELS,
    log:
        logfile("linear_report"),
    message:
        "Reproduction report rows of the linear part"
    script:
        "scripts/linear_report.py"


REPORT_PARTS.append(f"{R}/tables/report/linear.csv")
BOOK_INPUTS.extend(
    [table("eigen_summary"), table("table_4_1_model"), table("rd_summary")]
    + expand(interm("ps/{model}.npz"), model=LINEAR_MODELS)
    + expand(interm("eigen/{model}.npz"), model=LINEAR_MODELS)
)
