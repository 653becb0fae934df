"""Snakemake script: the quantitative claims of thesis Section 2 computed by the model.

Long table: bicycle, quantity, value, unit. NRMSDs (Eq 2.5) at the configured cadence, force
amplitudes and peaks, homogeneous (O) vs Winter (W) amplitude changes, the lateral-placement
variant of errata item 4, the cadence independence of errata item 7, the harmonic content of
Sec 2.2.2 and the reach of the city bicycle's original seat height (Sec 2.1.1).
"""

import sys

import numpy as np
import pandas as pd

from pedalrepro import disturbance, legs

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
w = float(snakemake.params.cadence_rpm) * 2 * np.pi / 60
samples = int(snakemake.params.samples)
NRMSD_KEYS = ("nrmsd_com_x_percent", "nrmsd_com_z_percent", "nrmsd_roll_torque_percent",
              "nrmsd_steer_torque_percent")


def unit(key: str) -> str:
    for suffix, u in (("_percent", "%"), ("_n", "N"), ("_deg", "deg"), ("_m", "m"),
                      ("_rad_s", "rad/s"), ("_ratio", "1")):
        if key.endswith(suffix):
            return u
    return ""


rows = []


def add(bicycle: str, key: str, value: float) -> None:
    if not np.isfinite(value):
        raise ValueError(f"{bicycle} {key} is not finite: {value}")
    rows.append({"bicycle": bicycle, "quantity": key, "value": float(value), "unit": unit(key)})


for bicycle in snakemake.params.bicycles:
    add(bicycle, "cadence_rad_s", w)
    numbers = disturbance.section2_numbers(bicycle, w, samples)
    for key, value in numbers.items():
        add(bicycle, key, value)
    seg = disturbance.section2_numbers(bicycle, w, samples, lateral="segments")
    for key in ("nrmsd_roll_torque_percent", "nrmsd_steer_torque_percent"):
        add(bicycle, key.replace("_percent", "_segments_percent"), seg[key])
    # errata 7: the NRMSDs at 0.6 and 1.7 times the cadence (not powers of 2: those scale exactly)
    spread = 0.0
    for factor in (0.6, 1.7):
        other = disturbance.section2_numbers(bicycle, factor * w, samples)
        spread = max(spread, *(abs(other[k] - numbers[k]) for k in NRMSD_KEYS))
    add(bicycle, "nrmsd_cadence_spread_percent", spread)
    # Sec 2.2.2: odd multiples cancel in the forces (and pitch), even ones in roll and yaw
    d = disturbance.pedalling_disturbance(bicycle, "O", w, samples_per_revolution=samples)
    f = np.abs(np.fft.rfft(d.force_n[:, [0, 2]], axis=0))
    t = np.abs(np.fft.rfft(d.torque_nm, axis=0))
    add(bicycle, "force_odd_harmonics_ratio", np.max(f[1::2]) / np.max(f))
    add(bicycle, "pitch_torque_odd_harmonics_ratio", np.max(t[1::2, 1]) / np.max(t[:, 1]))
    add(bicycle, "roll_yaw_torque_even_harmonics_ratio",
        np.max(t[0::2][:, [0, 2]]) / np.max(t[:, [0, 2]]))

# Sec 2.1.1 / errata 14: the city bicycle's original seat tube + post
params_city = legs.leg_geometry("city")
original = legs.params.legs()["seat_geometry"]["city"]["original_seat_tube_plus_post_m"]
bad = np.rad2deg(legs.unreachable_crank_angles_rad(params_city.with_seat(original)))
add("city", "original_seat_m", original)
add("city", "original_seat_unreachable_samples", bad.size)
if bad.size:
    add("city", "original_seat_unreachable_from_deg", bad.min())
    add("city", "original_seat_unreachable_to_deg", bad.max())
add("city", "used_seat_unreachable_samples", legs.unreachable_crank_angles_rad(params_city).size)
pd.DataFrame(rows).to_csv(snakemake.output.table, index=False, float_format="%.12g")
print(f"{len(rows)} numbers -> {snakemake.output.table}", file=sys.stderr)
