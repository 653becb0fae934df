# Rules of the nonlinear part (thesis Sec 3.1.1.3, 3.1.2.1, 3.2.4; see rules/common.smk):
# the symbolic models derived and compiled once (cached), their linearisations (benchmark vs
# Meijaard 2007, the four models' bodies vs Appendix B, Fig E.1), the NT/NP time-solution sweeps
# split by method, model and speed chunk, the RD maps of evaluation points 1a, 1b, 2a and
# PS vs NP (rule nonlinear_rd), their report rows (nonlinear_report, which only reads), and
# fig_3_34. CF and HS have their own arm loops (pedalrepro.nonlinear.arms, arm_design).

from pedalrepro import params as PARAMS

# The four systems, each with a non-linear model (pedalrepro.params.MODELS; fixed by the thesis,
# not configurable). The non-linear benchmark is linearised only (rule nonlinear_linearisation).
NONLINEAR_MODELS = list(PARAMS.MODELS)
NONLINEAR_CHUNKS = int(config["nonlinear"]["chunks"])
# Integration settings of the NT/NP runs (keyword arguments of nonlinear.sweep.RunSettings).
NONLINEAR_SETTINGS = dict(TIME_SAMPLES, **cfg("nonlinear", "rtol", "atol", "fall_roll_rad",
                                              "method"))
# The frames calibrated to Appendix B (rule nonlinear_calibration), read by every rule that
# builds a non-linear model (pedalrepro.nonlinear.calibration.use_file).
NONLINEAR_CALIBRATION = interm("nonlinear/calibration.yaml")
# The linear figures draw every time method for all four models, each of which has a non-linear
# model: TIME_METHODS (rules/linear.smk) gains NT and NP.
if "TIME_METHODS" in globals():
    TIME_METHODS.extend(["NT", "NP"])


# The four symbolic variants (plain Whipple for benchmark, HS, HR, CR; with CF's arm loops; each
# with and without the moving legs) are derived in separate jobs, so -j2 builds the two slow
# arm variants (about 100 s each) at once; the joined file is what later jobs wait for.
CODEGEN_VARIANTS = ["plain", "legs", "arms", "legs_arms"]


rule nonlinear_codegen_variant:
    input:
        code=code_inputs("scripts/nonlinear_codegen_variant.py"),
    output:
        interm("nonlinear/codegen/{variant}.txt"),
    wildcard_constraints:
        variant="|".join(CODEGEN_VARIANTS),
    threads: 1
    log:
        logfile("nonlinear_codegen_variant_{variant}"),
    benchmark:
        bench("nonlinear_codegen_variant_{variant}")
    message:
        "Deriving the non-linear model variant {wildcards.variant} with SymBRiM and generating "
        "its code (cached on disk: once)"
    script:
        "scripts/nonlinear_codegen_variant.py"


rule nonlinear_codegen:
    input:
        expand(interm("nonlinear/codegen/{variant}.txt"), variant=CODEGEN_VARIANTS),
    output:
        interm("nonlinear/codegen.txt"),
    log:
        logfile("nonlinear_codegen"),
    benchmark:
        bench("nonlinear_codegen")
    message:
        "All non-linear model variants generated"
    shell:
        "cat {input} > {output} 2> {log}"


rule nonlinear_calibration:
    input:
        code=code_inputs("scripts/nonlinear_calibration.py"),
        codegen=interm("nonlinear/codegen.txt"),
    output:
        table=table("calibration"),
        checks=table("calibration_checks"),
        record=NONLINEAR_CALIBRATION,
    params:
        models=NONLINEAR_MODELS,
    log:
        logfile("nonlinear_calibration"),
    benchmark:
        bench("nonlinear_calibration")
    message:
        "Calibrating the frames of {params.models} to thesis Appendix B (legs at crank angle 0)"
    script:
        "scripts/nonlinear_calibration.py"


rule nonlinear_linearisation:
    input:
        code=code_inputs("scripts/nonlinear_linearisation.py"),
        codegen=interm("nonlinear/codegen.txt"),
        calibration=NONLINEAR_CALIBRATION,
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
    benchmark:
        bench("nonlinear_linearisation")
    message:
        "Linearising the non-linear benchmark and {params.models} models; Fig E.1; energy check"
    script:
        "scripts/nonlinear_linearisation.py"


rule nonlinear_time_chunk:
    input:
        code=code_inputs("scripts/nonlinear_time_chunk.py"),
        codegen=interm("nonlinear/codegen.txt"),
        calibration=NONLINEAR_CALIBRATION,
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
    # longest first; before a first run here, NP (moving legs: dearer right-hand side) first
    priority: longest_first("nonlinear_time_chunk_{method}_{model}_{chunk}", lambda wc: wc.method == "NP")
    log:
        logfile("nonlinear_time_chunk_{method}_{model}_{chunk}"),
    benchmark:
        bench("nonlinear_time_chunk_{method}_{model}_{chunk}")
    message:
        "Non-linear time solutions ({wildcards.method}) of {wildcards.model}, speed chunk "
        "{wildcards.chunk}"
    script:
        "scripts/nonlinear_time_chunk.py"


rule nonlinear_time:
    input:
        code=code_inputs("scripts/nonlinear_time.py"),
        chunks=lambda wc: expand(interm("nonlinear/chunks/{method}_{model}_{chunk}.npz"),
                                 method=wc.method, model=wc.model,
                                 chunk=range(NONLINEAR_CHUNKS)),
    output:
        interm("time/{method}_{model}.npz"),
    params:
        grid=TIME_GRID,
        harmonics=HARMONICS,
        sample_rate_hz=TIME_SAMPLES["sample_rate_hz"],
    wildcard_constraints:
        method="NT|NP",
        model="|".join(NONLINEAR_MODELS),
    threads: 1
    log:
        logfile("nonlinear_time_{method}_{model}"),
    benchmark:
        bench("nonlinear_time_{method}_{model}")
    message:
        "Joining the {wildcards.method} sweep of {wildcards.model} (chunk 0 carries its six "
        "example runs)"
    script:
        "scripts/nonlinear_time.py"


rule nonlinear_rd:
    input:
        code=code_inputs("scripts/nonlinear_rd.py"),
        own=interm("nonlinear/linearisation_own.npz"),
        time=[interm(f"time/{method}_{model}.npz") for model in NONLINEAR_MODELS
              for method in ("NT", "NP")],
    output:
        maps=interm("nonlinear/rd_maps.npz"),
    params:
        models=NONLINEAR_MODELS,
        grid=TIME_GRID,
        samples=TIME_SAMPLES,
        harmonics=HARMONICS,
        fall_roll_rad=config["nonlinear"]["fall_roll_rad"],
    log:
        logfile("nonlinear_rd"),
    benchmark:
        bench("nonlinear_rd")
    message:
        "RD maps of the non-linear evaluation points 1a, 1b and PS vs NP (Fig 3.34)"
    script:
        "scripts/nonlinear_rd.py"


rule nonlinear_report:
    input:
        code=code_inputs("scripts/nonlinear_report.py"),
        maps=interm("nonlinear/rd_maps.npz"),
        benchmark=table("benchmark_linearisation"),
        appendix_b=table("linearisation_vs_appendix_b"),
        eigen_e_1=interm("nonlinear/eigen_cf_original_seat.npz"),
        eigen_cf=interm("nonlinear/eigen_cf_own.npz"),
    output:
        report=table("report/nonlinear"),
    log:
        logfile("nonlinear_report"),
    benchmark:
        bench("nonlinear_report")
    message:
        "Report rows of the non-linear part: linearisation, 1a, 1b, 2a, PS vs NP"
    script:
        "scripts/nonlinear_report.py"


REPORT_PARTS.append(table("report/nonlinear"))
BOOK_INPUTS.extend([
    table("calibration"),
    table("calibration_checks"),
    table("benchmark_linearisation"),
    table("linearisation_vs_appendix_b"),
    table("nonlinear_checks"),
    interm("nonlinear/rd_maps.npz"),
] + [interm(f"time/{method}_{model}.npz") for model in NONLINEAR_MODELS
     for method in ("NT", "NP")])
