# Rules of the section2 part (see rules/common.smk for helpers): thesis Section 2, the pedalling
# disturbance, and Appendix D (Table D.1; the figures: rules/figures.smk).

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
    benchmark:
        bench("section2_table_d_1")
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
    benchmark:
        bench("section2_disturbance_{bicycle}")
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
    benchmark:
        bench("section2_numbers")
    message:
        "Section 2 numbers: NRMSD (Eq 2.5), force amplitudes, O vs W, reach of the city leg"
    script:
        "scripts/section2_numbers.py"


rule section2_report:
    input:
        table_d_1=table("table_d_1"),
        numbers=table("section2_numbers"),
        code=code_inputs("scripts/section2_report.py"),
    output:
        report=table("report/section2"),
    log:
        logfile("section2_report"),
    benchmark:
        bench("section2_report")
    message:
        "Reproduction report rows of Section 2 and Table D.1"
    script:
        "scripts/section2_report.py"


REPORT_PARTS.append(table("report/section2"))
BOOK_INPUTS.extend(
    [table("table_d_1"), table("section2_numbers")]
    + [interm(f"section2/disturbance_{b}.npz") for b in SECTION2_BICYCLES]
)
