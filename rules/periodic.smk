# Beyond the thesis: periodic orbits of the non-linear models (pedalrepro.periodic).
# Shooting (single/multiple, half period) with Newton on the compiled right-hand side, Floquet
# multipliers, pseudo-arclength continuation in speed at the reference cadence. One map job per
# grid, method and model; one continuation job per model; a table job (figures: the registry). Every job
# building a model reads the calibrated frames (NONLINEAR_CALIBRATION) instead of re-solving
# the calibration (about 20 s per model and job).

from pedalrepro.periodic import maps as periodic_maps

PERIODIC = config["periodic"]


PERIODIC_GRIDS = {
    "thesis": {
        "speed_step_m_s": config["linear"]["time_speed_step_m_s"],
        "speed_max_m_s": config["linear"]["time_speed_max_m_s"],
        "omega_step_rad_s": config["linear"]["time_omega_step_rad_s"],
        "omega_max_rad_s": config["linear"]["time_omega_max_rad_s"],
    },
    "fine": {
        "speed_step_m_s": PERIODIC["fine_speed_step_m_s"],
        "speed_max_m_s": PERIODIC["fine_speed_max_m_s"],
        "omega_step_rad_s": PERIODIC["fine_omega_step_rad_s"],
        "omega_max_rad_s": PERIODIC["fine_omega_max_rad_s"],
    },
}
# A method mapped on both grids computes only the finer one when it contains the thesis grid
# (config/config.yaml: 0.2 m/s, 0.25 rad/s steps contain 0.4 m/s, 0.5 rad/s): rule
# periodic_map_subgrid cuts the thesis map out of it instead of solving those orbits twice.
PERIODIC_SUBGRID = [m for m in PERIODIC["methods"] if m in PERIODIC["fine_methods"]
                    and periodic_maps.nested(PERIODIC_GRIDS["thesis"], PERIODIC_GRIDS["fine"])]
PERIODIC_MAPS = [interm(f"periodic/thesis_{method}_{model}.npz")
                 for model in NONLINEAR_MODELS for method in PERIODIC["methods"]]
PERIODIC_FINE = [interm(f"periodic/fine_{method}_{model}.npz")
                 for model in NONLINEAR_MODELS for method in PERIODIC["fine_methods"]]
PERIODIC_BRANCHES = [interm(f"periodic/branch_{model}.npz") for model in NONLINEAR_MODELS]
PERIODIC_TABLES = [table("periodic_maps"), table("periodic_crossings"),
                   table("periodic_vs_simulation")]


rule periodic_map:
    input:
        code=code_inputs("scripts/periodic_map.py"),
        codegen=interm("nonlinear/codegen.txt"),
        calibration=NONLINEAR_CALIBRATION,
    output:
        interm("periodic/{grid}_{method}_{model}.npz"),
    wildcard_constraints:
        grid="thesis|fine",
        method="NT|NP",
        model="|".join(NONLINEAR_MODELS),
    params:
        grid=lambda wc: PERIODIC_GRIDS[wc.grid],
        rtol=PERIODIC["rtol"],
        max_growth=PERIODIC["max_growth"],
    threads: 1
    priority: longest_first("periodic_map_{grid}_{method}_{model}")
    log:
        logfile("periodic_map_{grid}_{method}_{model}"),
    benchmark:
        bench("periodic_map_{grid}_{method}_{model}")
    message:
        "Periodic orbits ({wildcards.method}) of {wildcards.model} on the {wildcards.grid} grid "
        "by shooting, with Floquet multipliers"
    script:
        "scripts/periodic_map.py"


rule periodic_map_subgrid:
    input:
        code=code_inputs("scripts/periodic_map_subgrid.py"),
        fine=interm("periodic/fine_{method}_{model}.npz"),
    output:
        interm("periodic/thesis_{method}_{model}.npz"),
    wildcard_constraints:
        method="|".join(PERIODIC_SUBGRID) or "(?!)",
        model="|".join(NONLINEAR_MODELS),
    params:
        grid=PERIODIC_GRIDS["thesis"],
    log:
        logfile("periodic_map_subgrid_{method}_{model}"),
    benchmark:
        bench("periodic_map_subgrid_{method}_{model}")
    message:
        "Periodic orbits ({wildcards.method}) of {wildcards.model} on the thesis grid, cut out "
        "of the finer grid's map"
    script:
        "scripts/periodic_map_subgrid.py"


ruleorder: periodic_map_subgrid > periodic_map


rule periodic_branch:
    input:
        code=code_inputs("scripts/periodic_branch.py"),
        codegen=interm("nonlinear/codegen.txt"),
        calibration=NONLINEAR_CALIBRATION,
    output:
        interm("periodic/branch_{model}.npz"),
    wildcard_constraints:
        model="|".join(NONLINEAR_MODELS),
    params:
        methods=PERIODIC["continuation_methods"],
        cadence_rpm=config["linear"]["reference_cadence_rpm"],
        speed_range_m_s=PERIODIC["continuation_speed_m_s"],
        torque_scales=PERIODIC["continuation_torque_scales"],
        ds=PERIODIC["continuation_ds"],
        rtol=PERIODIC["rtol"],
        max_growth=PERIODIC["max_growth"],
    threads: 1
    log:
        logfile("periodic_branch_{model}"),
    benchmark:
        bench("periodic_branch_{model}")
    message:
        "Continuation of the periodic orbits of {wildcards.model} in speed at "
        "{params.cadence_rpm} rpm ({params.methods}), multiplier crossings"
    script:
        "scripts/periodic_branch.py"


rule periodic_tables:
    input:
        code=code_inputs("scripts/periodic_tables.py"),
        calibration=NONLINEAR_CALIBRATION,
        maps=PERIODIC_MAPS,
        branches=PERIODIC_BRANCHES,
        time=[interm(f"time/{method}_{model}.npz") for model in NONLINEAR_MODELS
              for method in PERIODIC["methods"]],
    output:
        maps=table("periodic_maps"),
        crossings=table("periodic_crossings"),
        simulation=table("periodic_vs_simulation"),
    log:
        logfile("periodic_tables"),
    benchmark:
        bench("periodic_tables")
    message:
        "Tables of the periodic orbits: map summary, multiplier crossings, orbit vs simulation"
    script:
        "scripts/periodic_tables.py"


# The figures (periodic_maps_<model>, periodic_continuation, periodic_fine_maps) are in the
# figure registry (pedalrepro.figures.registry, group "periodic"): rule figures_periodic.
BOOK_INPUTS.extend(PERIODIC_MAPS + PERIODIC_FINE + PERIODIC_BRANCHES + PERIODIC_TABLES)
