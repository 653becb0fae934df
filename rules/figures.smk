# Every figure of every part, from ONE table: pedalrepro.figures.registry (id -> drawing
# function, the files it reads). One job per registry group draws its figures (PNG + PDF beside
# it, pedalrepro.figures.save); drawing only reads files. What the figures draw beyond the sweep
# rules' files is computed by the two figure-data rules below (pedalrepro.figdata), never while
# drawing. TIME_METHODS (rules/linear.smk, extended by rules/nonlinear.smk) says which optional
# time-solution files (NT, NP) this build has.
from pedalrepro import figdata as FIGDATA
from pedalrepro import params as PARAMS
from pedalrepro.figures import registry as FIGURE_REGISTRY

FIGURE_IDS = FIGURE_REGISTRY.ids()
# A group's code: the drawing script with the registry (which imports the drawing modules by
# name), plus the closure of the group's own drawing modules (FIGURE_REGISTRY.code_sources), so
# an edit reruns the figures that use it and no others.
FIGURE_SCRIPT_CODE = code_inputs("scripts/figures.py")

LINEAR_FIGURE_DATA = ["gear_grid", "cam_HS", "gear_sections_models", "gear_sections_benchmark"] + [
    f"neglected_{m}" for m in PARAMS.MODELS]


rule linear_figure_data:
    input:
        code=code_inputs("scripts/linear_figure_data.py"),
    output:
        **{name: interm(f"figures/{name}.npz") for name in LINEAR_FIGURE_DATA},
    params:
        linear=cfg("linear", *FIGDATA.LINEAR_KEYS),
    log:
        logfile("linear_figure_data"),
    benchmark:
        bench("linear_figure_data")
    message:
        "Arrays of Figs 3.8, 3.30, 3.31, F.1-F.3, 3.36 and G.8 (CAM, neglected momenta, gears)"
    script:
        "scripts/linear_figure_data.py"


rule validation_figure_data:
    input:
        code=code_inputs("scripts/validation_figure_data.py"),
        per_run=table("validation_runs"),
        series=interm("mocap/series.npz"),
        source=interm("mocap/source.json"),
        spectra=interm("closed_loop/spectra.csv"),
    output:
        interm("figures/validation.npz"),
    params:
        linear=cfg("linear", "ps_speed_step_m_s", "ps_speed_max_m_s", "ps_omega_step_rad_s",
                   "ps_omega_max_rad_s"),
        examples=config["mocap"]["example_runs_per_system"],
    log:
        logfile("validation_figure_data"),
    benchmark:
        bench("validation_figure_data")
    message:
        "Model maps and series of the example runs of Figs 4.2-4.10, the CF spectra's points and the REAL run"
    script:
        "scripts/validation_figure_data.py"


for _group in FIGURE_REGISTRY.groups():

    rule:
        name:
            f"figures_{_group}"
        input:
            code=sorted(set(FIGURE_SCRIPT_CODE) | set(code_inputs(
                *(f"../{src}" for src in FIGURE_REGISTRY.code_sources(_group))))),
            data=lambda wc, g=_group: sorted(
                {p for f in FIGURE_REGISTRY.ids(group=g)
                 for p in FIGURE_REGISTRY.inputs(f, R, TIME_METHODS)}
            ),
        output:
            png=[figure(f) for f in FIGURE_REGISTRY.ids(group=_group)],
            pdf=[figure(f, "pdf") for f in FIGURE_REGISTRY.ids(group=_group)],
        params:
            time_methods=lambda wc: list(TIME_METHODS),
        log:
            logfile(f"figures_{_group}"),
        benchmark:
            bench(f"figures_{_group}")
        message:
            f"Figures of group {_group} (pedalrepro.figures.registry)"
        script:
            "scripts/figures.py"


BOOK_INPUTS.extend([figure(f) for f in FIGURE_IDS] + [figure(f, "pdf") for f in FIGURE_IDS])
