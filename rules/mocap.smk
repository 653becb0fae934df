# Rules of the mocap part (see rules/common.smk for helpers): the treadmill data (Sec 4.1),
# Tables 4.1 and 4.2 and Figures 4.2-4.11. data_source (config): auto | figshare | synthetic
# (pedalrepro.mocap.prepare): auto = figshare when it can be had, else the stand-in plus the real
# public-subset runs in $PEDALREPRO_DATA_DIR (or downloadable), each row labelled (data_source
# column: figshare | synthetic | public_subset; SYNTHETIC stamp; report status "not reproducible
# here" for synthetic rows). The data folder is not a tracked input: after adding files to it,
# rerun with `snakemake -j2 -R mocap_runs`.

# The mocap keys the synthetic stand-in uses (pedalrepro.mocap.synthetic, its `mocap_cfg`).
MOCAP_STAND_IN_KEYS = ["duration_s", "sample_rate_hz", "marker_noise_m", "gaps_per_marker_per_min",
                       "max_gap_s", "repair_gap_max_s", "max_runs_per_system",
                       "stand_in_gear_ratios", "stand_in_cadence_rpm"]


rule mocap_runs:
    input:
        code=code_inputs("scripts/mocap_runs.py"),
    output:
        runs=directory(interm("mocap/runs")),
        source=interm("mocap/source.json"),
    params:
        data_source=config["data_source"],
        mocap=cfg("mocap", *MOCAP_STAND_IN_KEYS),
        seed=config["seed"],
    log:
        logfile("mocap_runs"),
    benchmark:
        bench("mocap_runs")
    message:
        "Treadmill run files (data_source: {params.data_source}; offline: stand-in + real subset)"
    script:
        "scripts/mocap_runs.py"


rule mocap_extract:
    input:
        runs=interm("mocap/runs"),
        source=interm("mocap/source.json"),
        code=code_inputs("scripts/mocap_extract.py"),
    output:
        table=interm("mocap/measured.csv"),
        series=interm("mocap/series.npz"),
        excluded=interm("mocap/excluded.csv"),
    params:
        lowpass_hz=config["mocap"]["angle_lowpass_hz"],
    log:
        logfile("mocap_extract"),
    benchmark:
        bench("mocap_extract")
    message:
        "Roll, steer, yaw and cadence of every treadmill run (rigid-body fits, Hann DFT)"
    script:
        "scripts/mocap_extract.py"


CHAPTER_4_INPUTS = dict(
    measured=interm("mocap/measured.csv"),
    runs=interm("mocap/runs"),
    source=interm("mocap/source.json"),
    model=table("table_4_1_model"),
)


rule validation_tables:
    input:
        **CHAPTER_4_INPUTS,
        code=code_inputs("scripts/validation_tables.py"),
    output:
        t41=table("table_4_1"),
        t42=table("table_4_2"),
        per_run=table("validation_runs"),
        comparison=table("mocap_real_comparison"),
    log:
        logfile("validation_tables"),
    benchmark:
        bench("validation_tables")
    message:
        "Tables 4.1 and 4.2: measured vs open-loop model cadence amplitudes"
    script:
        "scripts/validation_tables.py"


# The report rows of chapter 4 (claims.yaml): a rule of their own that only reads, so that no
# table or figure depends on the claims.
rule validation_report:
    input:
        **CHAPTER_4_INPUTS,
        code=code_inputs("scripts/validation_report.py"),
    output:
        report=table("report/mocap"),
    log:
        logfile("validation_report"),
    benchmark:
        bench("validation_report")
    message:
        "Report rows of Tables 4.1 and 4.2 and of the real run (claims.yaml)"
    script:
        "scripts/validation_report.py"


REPORT_PARTS.append(table("report/mocap"))
# Figures 4.2-4.11 and the REAL run's panel are drawn by rules/figures.smk (figure registry).
BOOK_INPUTS.extend(
    [table("table_4_1"), table("table_4_2"), table("validation_runs"),
     table("mocap_real_comparison"), interm("mocap/source.json"), interm("mocap/series.npz"),
     interm("mocap/excluded.csv"), interm("mocap/measured.csv")]
)
