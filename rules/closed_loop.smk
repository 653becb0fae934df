# Beyond the thesis: the rider closes the loop (pedalrepro.rider; see rules/common.smk for the
# helpers). Gains by the Hess-Moore-Hubbard / HumanControl rules and closed-loop eigenvalues
# against speed, closed-loop pedalling maps, Moore's measured CF spectra (data/registry_spectra.txt:
# from $PEDALREPRO_DATA_DIR offline, downloaded when missing; not a tracked input: after adding
# the files, rerun with -R closed_loop_spectra), and open vs closed loop vs measurement.
CLOSED_LOOP = config["closed_loop"]
CLOSED_LOOP_MAPS = [interm(f"closed_loop/map_{m}.npz") for m in CLOSED_LOOP["map_models"]]
CLOSED_LOOP_TABLES = [table("closed_loop_validation"), table("rider_gains"),
                      table("table_4_2_closed_loop"), table("steer_stiffness"),
                      table("lean_rider")]
CLOSED_LOOP_FIGURES = [figure("closed_loop_validation"), figure("closed_loop_gains"),
                       figure("closed_loop_maps"), figure("closed_loop_time")]


rule closed_loop_gains:
    input:
        code=code_inputs("scripts/closed_loop_gains.py"),
    output:
        gains=table("rider_gains"),
        eigen=interm("closed_loop/eigen.npz"),
        maps=CLOSED_LOOP_MAPS,
    params:
        closed_loop=CLOSED_LOOP,
        harmonics=HARMONICS,
    log:
        logfile("closed_loop_gains"),
    benchmark:
        bench("closed_loop_gains")
    message:
        "Rider gains (HumanControl rules), closed-loop eigenvalues and maps of {params.closed_loop[map_models]}"
    script:
        "scripts/closed_loop_gains.py"


rule closed_loop_lean:
    input:
        code=code_inputs("scripts/closed_loop_lean.py"),
    output:
        table=table("lean_rider"),
    params:
        closed_loop=cfg("closed_loop", "map_speed_min_m_s", "speed_max_m_s", "map_speed_step_m_s"),
    log:
        logfile("closed_loop_lean"),
    benchmark:
        bench("closed_loop_lean")
    message:
        "Hands-free lean-torque rider on the leaning-rider plant (Browser + Jason): the gain rules on T9"
    script:
        "scripts/closed_loop_lean.py"


rule closed_loop_spectra:
    input:
        code=code_inputs("scripts/closed_loop_spectra.py"),
    output:
        table=interm("closed_loop/spectra.csv"),
        arrays=interm("closed_loop/spectra.npz"),
        status=interm("closed_loop/spectra.json"),
    log:
        logfile("closed_loop_spectra"),
    benchmark:
        bench("closed_loop_spectra")
    message:
        "Measured closed-loop spectra of CF (Moore's MotionCapture figures, sha256-checked)"
    script:
        "scripts/closed_loop_spectra.py"


rule closed_loop_validation:
    input:
        code=code_inputs("scripts/closed_loop_validation.py"),
        spectra=interm("closed_loop/spectra.csv"),
        status=interm("closed_loop/spectra.json"),
        measured=interm("mocap/measured.csv"),
        gains=table("rider_gains"),
    output:
        validation=table("closed_loop_validation"),
        t42=table("table_4_2_closed_loop"),
        stiffness=table("steer_stiffness"),
        time=interm("closed_loop/time_CF.npz"),
    params:
        closed_loop=CLOSED_LOOP,
        harmonics=HARMONICS,
    log:
        logfile("closed_loop_validation"),
    benchmark:
        bench("closed_loop_validation")
    message:
        "Open loop vs closed loop vs measurement (Table 4.1, run {params.closed_loop[real_run]}, CF spectra)"
    script:
        "scripts/closed_loop_validation.py"


rule closed_loop_report:
    input:
        code=code_inputs("scripts/closed_loop_report.py"),
        status=interm("closed_loop/spectra.json"),
        t42=table("table_4_2_closed_loop"),
        gains=table("rider_gains"),
    output:
        table("report/closed_loop"),
    log:
        logfile("closed_loop_report"),
    benchmark:
        bench("closed_loop_report")
    message:
        "Reproduction report rows of the closed loop (Table 4.2 CF from the spectra, gains)"
    script:
        "scripts/closed_loop_report.py"


rule closed_loop_figures:
    input:
        code=code_inputs("scripts/closed_loop_figures.py"),
        validation=table("closed_loop_validation"),
        eigen=interm("closed_loop/eigen.npz"),
        maps=CLOSED_LOOP_MAPS,
        time=interm("closed_loop/time_CF.npz"),
    output:
        CLOSED_LOOP_FIGURES,
    log:
        logfile("closed_loop_figures"),
    benchmark:
        bench("closed_loop_figures")
    message:
        "Figures of the closed loop: open vs closed vs measured, gains and eigenvalues, maps"
    script:
        "scripts/closed_loop_figures.py"


REPORT_PARTS.append(table("report/closed_loop"))
BOOK_INPUTS.extend(CLOSED_LOOP_TABLES + CLOSED_LOOP_MAPS + CLOSED_LOOP_FIGURES
                   + [interm("closed_loop/eigen.npz"), interm("closed_loop/time_CF.npz"), interm("closed_loop/spectra.csv"),
                      interm("closed_loop/spectra.json")])
