# Rules of the nonlinear part (thesis Sec 3.1.1.3, 3.1.2.1, 3.2.4; see rules/common.smk):
# the symbolic models derived and compiled once (cached), their linearisations (benchmark vs
# Meijaard 2007, the four models' bodies vs Appendix B, Fig E.1), the NT/NP time-solution sweeps
# split by method, model and speed chunk, the report rows of evaluation points 1a, 1b, 2a,
# PS vs NP, and fig_3_34. CF has its own arm loops (pedalrepro.nonlinear.arms); HS is a
# substitute (pedalrepro.nonlinear.substitute).

NONLINEAR_MODELS = list(config["nonlinear"]["models"])
NONLINEAR_CHUNKS = int(config["nonlinear"]["chunks"])
# Integration settings of the NT/NP runs (keyword arguments of nonlinear.sweep.RunSettings).
NONLINEAR_SETTINGS = dict(TIME_SAMPLES, **cfg("nonlinear", "rtol", "atol", "fall_roll_rad",
                                              "method"))
# The linear figures draw every time method for all four models, so TIME_METHODS gains NT and NP
# only when all four have a non-linear model (config nonlinear.models).
if "TIME_METHODS" in globals() and set(NONLINEAR_MODELS) >= {"HS", "CF", "HR", "CR"}:
    TIME_METHODS.extend(["NT", "NP"])


# The four symbolic variants (plain Whipple for benchmark, HS, HR, CR; with CF's arm loops; each
# with and without the moving legs) are derived in separate jobs, so -j2 builds the two slow
# arm variants (about 100 s each) at once; the joined file is what later jobs wait for.
CODEGEN_VARIANTS = ["plain", "legs", "arms", "legs_arms"]


rule nonlinear_codegen_variant:
    input:
        code=code_inputs("scripts/nonlinear_codegen.py"),
    output:
        interm("nonlinear/codegen/{variant}.txt"),
    wildcard_constraints:
        variant="|".join(CODEGEN_VARIANTS),
    threads: 1
    log:
        logfile("nonlinear_codegen_{variant}"),
    benchmark:
        bench("nonlinear_codegen_{variant}")
    message:
        "Deriving the non-linear model variant {wildcards.variant} with SymBRiM and generating "
        "its code (cached on disk: once)"
    script:
        "scripts/nonlinear_codegen.py"


rule nonlinear_codegen:
    input:
        expand(interm("nonlinear/codegen/{variant}.txt"), variant=CODEGEN_VARIANTS),
    output:
        interm("nonlinear/codegen.txt"),
    log:
        logfile("nonlinear_codegen"),
    message:
        "All non-linear model variants generated"
    shell:
        "cat {input} > {output} 2> {log}"


rule nonlinear_linearisation:
    input:
        code=code_inputs("scripts/nonlinear_linearisation.py"),
        codegen=interm("nonlinear/codegen.txt"),
        meijaard="data/published/meijaard2007.yaml",
    output:
        benchmark=table("benchmark_linearisation"),
        appendix_b=table("linearisation_vs_appendix_b"),
        checks=table("nonlinear_checks"),
        own=interm("nonlinear/linearisation_own.npz"),
        eigen_e_1=interm("nonlinear/eigen_cf_original_seat.npz"),
        eigen_cf_own=interm("nonlinear/eigen_cf_own.npz"),
    params:
        models=NONLINEAR_MODELS,
        eigen_speeds=EIGEN_SPEEDS,
    log:
        logfile("nonlinear_linearisation"),
    message:
        "Linearising the non-linear benchmark and {params.models} models; Fig E.1; energy check"
    script:
        "scripts/nonlinear_linearisation.py"


rule nonlinear_time_chunk:
    input:
        code=code_inputs("scripts/nonlinear_time.py"),
        codegen=interm("nonlinear/codegen.txt"),
    output:
        interm("nonlinear/chunks/{method}_{model}_{chunk}.npz"),
    params:
        chunks=NONLINEAR_CHUNKS,
        grid=TIME_GRID,
        harmonics=HARMONICS,
        settings=NONLINEAR_SETTINGS,
    wildcard_constraints:
        method="NT|NP",
        model="|".join(NONLINEAR_MODELS),
        chunk=r"\d+",
    threads: 1
    log:
        logfile("nonlinear_time_{method}_{model}_{chunk}"),
    benchmark:
        bench("nonlinear_time_{method}_{model}_{chunk}")
    message:
        "Non-linear time solutions ({wildcards.method}) of {wildcards.model}, speed chunk "
        "{wildcards.chunk}"
    script:
        "scripts/nonlinear_time.py"


rule nonlinear_time:
    input:
        code=code_inputs("scripts/nonlinear_merge.py"),
        chunks=lambda wc: expand(interm("nonlinear/chunks/{method}_{model}_{chunk}.npz"),
                                 method=wc.method, model=wc.model,
                                 chunk=range(NONLINEAR_CHUNKS)),
    output:
        interm("time/{method}_{model}.npz"),
    params:
        grid=TIME_GRID,
        harmonics=HARMONICS,
        settings=NONLINEAR_SETTINGS,
    wildcard_constraints:
        method="NT|NP",
        model="|".join(NONLINEAR_MODELS),
    threads: 1
    log:
        logfile("nonlinear_time_{method}_{model}"),
    benchmark:
        bench("nonlinear_time_{method}_{model}")
    message:
        "Joining the {wildcards.method} sweep of {wildcards.model} and its six example runs"
    script:
        "scripts/nonlinear_merge.py"


rule nonlinear_report:
    input:
        code=code_inputs("scripts/nonlinear_report.py"),
        benchmark=table("benchmark_linearisation"),
        appendix_b=table("linearisation_vs_appendix_b"),
        own=interm("nonlinear/linearisation_own.npz"),
        eigen_e_1=interm("nonlinear/eigen_cf_original_seat.npz"),
        eigen_cf=interm("nonlinear/eigen_cf_own.npz"),
        time=[interm(f"time/{method}_{model}.npz") for model in NONLINEAR_MODELS
              for method in ("NT", "NP")],
        meijaard="data/published/meijaard2007.yaml",
        published="data/published/thesis_values.yaml",
    output:
        report=f"{R}/tables/report/nonlinear.csv",
        maps=interm("nonlinear/rd_maps.npz"),
    params:
        models=NONLINEAR_MODELS,
        grid=TIME_GRID,
        samples=TIME_SAMPLES,
        harmonics=HARMONICS,
        fall_roll_rad=config["nonlinear"]["fall_roll_rad"],
    log:
        logfile("nonlinear_report"),
    message:
        "Report rows of the non-linear part: linearisation, 1a, 1b, 2a, PS vs NP"
    script:
        "scripts/nonlinear_report.py"


rule nonlinear_figure:
    input:
        code=code_inputs("scripts/nonlinear_figure.py"),
        maps=interm("nonlinear/rd_maps.npz"),
        appendix_b=table("linearisation_vs_appendix_b"),
        eigen_e_1=interm("nonlinear/eigen_cf_original_seat.npz"),
        eigen_cf=interm("nonlinear/eigen_cf_own.npz"),
    output:
        fig_3_34=figure("fig_3_34"),
        appendix_b=figure("nonlinear_linearisation_vs_appendix_b"),
        fig_e_1=figure("fig_e_1"),
    log:
        logfile("nonlinear_figure"),
    message:
        "Figures of the non-linear part: fig_3_34, fig_e_1 and the Appendix B comparison"
    script:
        "scripts/nonlinear_figure.py"


REPORT_PARTS.append(f"{R}/tables/report/nonlinear.csv")
BOOK_INPUTS.extend([
    table("benchmark_linearisation"),
    table("linearisation_vs_appendix_b"),
    table("nonlinear_checks"),
    interm("nonlinear/rd_maps.npz"),
    figure("fig_3_34"),
    figure("fig_e_1"),
    figure("nonlinear_linearisation_vs_appendix_b"),
] + [interm(f"time/{method}_{model}.npz") for model in NONLINEAR_MODELS
     for method in ("NT", "NP")])
