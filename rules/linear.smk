# Rules of the linear part (thesis Sec 3, linear methods; see rules/common.smk for helpers):
# eigen analysis, particular solution (PS), time solutions (LA analytic, LN numerical), RD maps,
# Table 4.1 model columns and the report part (the figures: rules/figures.smk).

from pedalrepro import params as PARAMS

# The linear models, fixed by the thesis (pedalrepro.params.LINEAR_MODELS: the Meijaard benchmark
# and the four systems of pedalrepro.params.MODELS); not configurable (another bicycle: rule
# own_bicycle_resonance, config section own_bicycle).
LINEAR_MODELS = list(PARAMS.LINEAR_MODELS)
# Time solutions and RD maps: the four thesis models (the benchmark has PS and eigen figures only).
LINEAR_TIME_MODELS = [m for m in LINEAR_MODELS if m != "benchmark"]
# Time-solution methods drawn in fig_3_10 .. fig_3_33, fig_g_*, fig_h_*. rules/nonlinear.smk
# (included after this file) extends it with "NT", "NP"; inputs read it lazily.
TIME_METHODS = ["LA", "LN"]

rule linear_eigen:
    input:
        code=code_inputs("scripts/linear_eigen.py"),
    output:
        table=table("eigen_summary"),
        sweeps=expand(interm("eigen/{model}.npz"), model=LINEAR_MODELS),
    params:
        models=LINEAR_MODELS,
        eigen_speeds=EIGEN_SPEEDS,
    log:
        logfile("linear_eigen"),
    benchmark:
        bench("linear_eigen")
    message:
        "Eigenvalues vs speed, weave/capsize speeds and self-stable ranges of {params.models}"
    script:
        "scripts/linear_eigen.py"


rule linear_ps:
    input:
        code=code_inputs("scripts/linear_ps.py"),
    output:
        npz=expand(interm("ps/{model}.npz"), model=LINEAR_MODELS),
    params:
        models=LINEAR_MODELS,
        grid=PS_GRID,
        harmonics=HARMONICS,
        reference=cfg("linear", "reference_speed_m_s", "reference_cadence_rpm"),
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
        code=code_inputs("scripts/linear_time.py"),
    output:
        npz=expand(interm("time/LA_{model}.npz"), model=LINEAR_TIME_MODELS),
    params:
        method="LA",
        models=LINEAR_TIME_MODELS,
        grid=TIME_GRID,
        samples=TIME_SAMPLES,
        harmonics=HARMONICS,
        fall_roll_rad=config["linear"]["fall_roll_rad"],
    threads: 1
    log:
        logfile("linear_time_la"),
    benchmark:
        bench("linear_time_la")
    message:
        "Analytic time solutions (LA) of {params.models} on the time grid"
    script:
        "scripts/linear_time.py"


# LN through the compiled Dormand-Prince integrator (about 2 s per model on the thesis
# grid, the job's start-up included) is, like LA, one job for all models.
rule linear_time_ln:
    input:
        code=code_inputs("scripts/linear_time.py"),
    output:
        npz=expand(interm("time/LN_{model}.npz"), model=LINEAR_TIME_MODELS),
    params:
        method="LN",
        models=LINEAR_TIME_MODELS,
        grid=TIME_GRID,
        samples=TIME_SAMPLES,
        harmonics=HARMONICS,
        fall_roll_rad=config["linear"]["fall_roll_rad"],
        tolerances=cfg("linear", "rtol", "atol", "tight_rtol", "tight_atol"),
    threads: 1
    log:
        logfile("linear_time_ln"),
    benchmark:
        bench("linear_time_ln")
    message:
        "Numerical time solutions (LN) of {params.models} on the time grid"
    script:
        "scripts/linear_time.py"


rule linear_rd:
    input:
        code=code_inputs("scripts/linear_rd.py"),
        ps=expand(interm("ps/{model}.npz"), model=LINEAR_TIME_MODELS),
        la=expand(interm("time/LA_{model}.npz"), model=LINEAR_TIME_MODELS),
        ln=expand(interm("time/LN_{model}.npz"), model=LINEAR_TIME_MODELS),
    output:
        maps=expand(interm("rd/{model}.npz"), model=LINEAR_TIME_MODELS),
        pairs=interm("rd/pairs.npz"),
        table=table("rd_summary"),
    params:
        models=LINEAR_TIME_MODELS,
        harmonics=HARMONICS,
        normal_cycling=cfg("linear", "normal_cycling_speed_kmh", "normal_cycling_cadence_rpm"),
    log:
        logfile("linear_rd"),
    benchmark:
        bench("linear_rd")
    message:
        "Relative-difference maps of evaluation points 1c, 2b, 3a, 3b, 4, 5, 6 (Eq 3.26)"
    script:
        "scripts/linear_rd.py"


rule linear_table_4_1:
    input:
        code=code_inputs("scripts/linear_table_4_1.py"),
        runs="data/parameters/validation_runs.yaml",
    output:
        table=table("table_4_1_model"),
        moved=table("table_4_1_model_moved_inputs"),
    params:
        harmonics=HARMONICS,
    log:
        logfile("linear_table_4_1"),
    benchmark:
        bench("linear_table_4_1")
    message:
        "Table 4.1 model columns: particular solution at the seven hands-free runs"
    script:
        "scripts/linear_table_4_1.py"


rule linear_report:
    input:
        code=code_inputs("scripts/linear_report.py"),
        eigen=table("eigen_summary"),
        rd=table("rd_summary"),
        table_4_1=table("table_4_1_model"),
        table_4_1_moved=table("table_4_1_model_moved_inputs"),
        ps=expand(interm("ps/{model}.npz"), model=LINEAR_MODELS),
    output:
        report=table("report/linear"),
        sensitivity=table("sensitivity"),
    params:
        models=LINEAR_MODELS,
        profile=config["profile"],
        harmonics=HARMONICS,
        eigen_speeds=EIGEN_SPEEDS,
        lin=cfg("linear", "normal_cycling_speed_kmh", "normal_cycling_cadence_rpm", "gear_ratios",
                "ps_omega_max_rad_s", "duration_s", "sample_rate_hz", "rtol", "atol"),
    log:
        logfile("linear_report"),
    benchmark:
        bench("linear_report")
    message:
        "Reproduction report rows of the linear part"
    script:
        "scripts/linear_report.py"


REPORT_PARTS.append(table("report/linear"))
BOOK_INPUTS.extend(
    [table("eigen_summary"), table("table_4_1_model"), table("rd_summary")]
    + [table("sensitivity"), table("table_4_1_model_moved_inputs")]
    + expand(interm("ps/{model}.npz"), model=LINEAR_MODELS)
    + expand(interm("eigen/{model}.npz"), model=LINEAR_MODELS)
)
