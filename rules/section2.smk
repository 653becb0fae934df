# Rules of the section2 part (see rules/common.smk for helpers): thesis Section 2, the pedalling
# disturbance, and Appendix D (Table D.1, Fig D.1).

SECTION2_FIGURES = ["fig_2_2", "fig_2_3", "fig_2_4", "fig_2_5", "fig_2_6", "fig_2_7", "fig_d_1"]
SECTION2_BICYCLES = ["hybrid", "city"]


rule section2_table_d_1:
    input:
        code=code_inputs("scripts/section2_table_d_1.py"),
    output:
        table=table("table_d_1"),
    params:
        samples=config["section2"]["samples_per_revolution"],
        harmonics=config["section2"]["harmonics"],
    log:
        logfile("section2_table_d_1"),
    message:
        "Table D.1: Fourier coefficients of the leg COM (dual four-bar), 4 cases"
    script:
        "scripts/section2_table_d_1.py"


rule section2_disturbance:
    input:
        code=code_inputs("scripts/section2_disturbance.py"),
    output:
        npz=interm("section2/disturbance_{bicycle}.npz"),
    params:
        cadence_rpm=config["section2"]["cadence_rpm"],
        samples=config["section2"]["samples_per_revolution"],
    wildcard_constraints:
        bicycle="hybrid|city",
    log:
        logfile("section2_disturbance_{bicycle}"),
    message:
        "Leg kinematics, d'Alembert forces and torques of the {wildcards.bicycle} bicycle"
    script:
        "scripts/section2_disturbance.py"


rule section2_numbers:
    input:
        code=code_inputs("scripts/section2_numbers.py"),
    output:
        table=table("section2_numbers"),
    params:
        cadence_rpm=config["section2"]["cadence_rpm"],
        samples=config["section2"]["samples_per_revolution"],
        bicycles=SECTION2_BICYCLES,
    log:
        logfile("section2_numbers"),
    message:
        "Section 2 numbers: NRMSD (Eq 2.5), force amplitudes, O vs W, reach of the city leg"
    script:
        "scripts/section2_numbers.py"


rule section2_figure:
    input:
        npz=interm("section2/disturbance_hybrid.npz"),
        code=code_inputs("scripts/section2_figure.py"),
    output:
        png=figure("{fid}"),
    wildcard_constraints:
        fid="|".join(SECTION2_FIGURES),
    log:
        logfile("section2_{fid}"),
    message:
        "Section 2 figure {wildcards.fid}"
    script:
        "scripts/section2_figure.py"


rule section2_report:
    input:
        table_d_1=table("table_d_1"),
        numbers=table("section2_numbers"),
        published="data/published/thesis_values.yaml",
        code=code_inputs("scripts/section2_report.py"),
    output:
        report=f"{R}/tables/report/section2.csv",
    log:
        logfile("section2_report"),
    message:
        "Reproduction report rows of Section 2 and Table D.1"
    script:
        "scripts/section2_report.py"


REPORT_PARTS.append(f"{R}/tables/report/section2.csv")
BOOK_INPUTS.extend(
    [table("table_d_1"), table("section2_numbers")]
    + [figure(f) for f in SECTION2_FIGURES]
    + [interm(f"section2/disturbance_{b}.npz") for b in SECTION2_BICYCLES]
)
