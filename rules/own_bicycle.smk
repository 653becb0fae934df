# "Your own bicycle": the pedalling resonance of a bicycle the thesis did not
# study, from BicycleParameters' files (pedalrepro.own_bicycle; also `pedalrepro resonance`).

# The shipped Rigid bicycle (BicycleParameters 1.5.2) with rider Jason. Its lst + lsp = 0.751 m
# leaves the 0.92 m legs of legs.yaml 0.9 mm short of the pedal: the hip is set at 0.72 m, as the
# thesis shortened the Browser's seat post (Sec 2.1.1).
OWN_DATA_DIR = "data/parameters/bicycleparameters"
OWN_BICYCLE = dict(bicycle="Rigid", rider="Jason", seat_height_m=0.72)
OWN_STEM = f"{OWN_BICYCLE['bicycle']}_{OWN_BICYCLE['rider']}"


rule own_bicycle_resonance:
    input:
        # the script, its import closure and the example's files (own_bicycle.DATA_FILES)
        code=code_inputs("scripts/own_bicycle_resonance.py"),
        data_dir=OWN_DATA_DIR,
    output:
        map=table(f"own_bicycle/{OWN_STEM}_resonance_map"),
        summary=table(f"own_bicycle/{OWN_STEM}_summary"),
        png=figure(f"own_bicycle/{OWN_STEM}_resonance"),
    params:
        linear=cfg("linear", "ps_speed_step_m_s", "ps_speed_max_m_s", "ps_omega_step_rad_s",
                   "ps_omega_max_rad_s", "eigen_speed_step_m_s", "eigen_speed_max_m_s",
                   "harmonics", "gear_ratios", "normal_cycling_speed_kmh",
                   "normal_cycling_cadence_rpm"),
        **OWN_BICYCLE,
    log:
        logfile("own_bicycle_resonance"),
    benchmark:
        bench("own_bicycle_resonance")
    message:
        "Your own bicycle: eigenvalues and PS resonance map of {params.bicycle} + {params.rider}"
    script:
        "scripts/own_bicycle_resonance.py"


BOOK_INPUTS.extend(rules.own_bicycle_resonance.output)
