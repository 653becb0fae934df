"""Snakemake script: rider gains and closed-loop eigenvalues against speed, the gains at the
published tables' speeds, and the closed-loop pedalling maps (pedalrepro.rider)."""

import sys

import numpy as np
import pandas as pd

from pedalrepro import params, paths, response
from pedalrepro.rider import closed_loop, comparison

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
c = snakemake.params.closed_loop
speeds = np.round(np.arange(c["speed_min_m_s"], c["speed_max_m_s"] + 1e-9,
                            c["speed_step_m_s"]), 9)
rows, eig = [], {}
published = params.read_yaml(paths.PUBLISHED / "humancontrol_gains.yaml")
tables = {"benchmark": "Benchmark", "humancontrol_browser": "Browser"}
for name in c["steer_models"]:
    extra = [r[0] for r in published.get(tables.get(name, ""), [])]
    grid = np.union1d(speeds, extra)
    sweep = closed_loop.gain_sweep(name, grid)
    for v, g in zip(sweep.speed_m_s, sweep.gains, strict=True):
        rows.append({"model": name, "speed_m_s": v, **dict(zip(
            ["kDelta", "kPhiDot", "kPhi", "kPsi", "kY"], g, strict=True)),
            "source": "rules (generate_data.m: damping 0.1289/0.0855, crossovers 2/1/0.5 rad/s)"})
    eig[name] = sweep
    for v, why in sweep.failed.items():
        print(f"{name} {v} m/s: {why}", file=sys.stderr)
    print(f"{name}: closed loop unstable at {sweep.speed_m_s[~sweep.stable].tolist()} m/s",
          file=sys.stderr)
for name, key in tables.items():
    for r in published[key]:
        rows.append({"model": name, "speed_m_s": r[0], **dict(zip(
            ["kDelta", "kPhiDot", "kPhi", "kPsi", "kY"], r[1:], strict=True)),
            "source": f"published (HumanControl gains/{key}SteerGains.txt)"})
for r in published["BenchmarkRoll"]:
    rows.append({"model": "benchmark (roll torque)", "speed_m_s": r[0], **dict(zip(
        ["kDelta", "kPhiDot", "kPhi", "kPsi", "kY"], r[1:], strict=True)),
        "source": "published (HumanControl gains/BenchmarkRollGains.txt)"})
pd.DataFrame(rows, columns=list(comparison.GAIN_COLUMNS)).to_csv(
    snakemake.output.gains, index=False, float_format="%.6g")
np.savez(snakemake.output.eigen, models=np.array(list(eig)),
         **{f"{k}_speed_m_s": s.speed_m_s for k, s in eig.items()},
         **{f"{k}_eigenvalues": s.eigenvalues for k, s in eig.items()},
         **{f"{k}_stable": s.stable for k, s in eig.items()},
         **{f"{k}_gains": s.gains for k, s in eig.items()})

# closed-loop pedalling maps (PS grid of the closed loop)
v_map = np.round(np.arange(c["map_speed_min_m_s"], c["speed_max_m_s"] + 1e-9,
                           c["map_speed_step_m_s"]), 9)
w_map = response.grid(c["map_omega_step_rad_s"], c["map_omega_max_rad_s"])
for name, path in zip(c["map_models"], snakemake.output.maps, strict=True):
    h = response.forcing(name, snakemake.params.harmonics)
    k1 = int(np.nonzero(h.n == 1)[0][0])
    g, stable, control = comparison.rider_gains(name, v_map)
    roll, steer = closed_loop.closed_loop_particular(name, v_map, g, w_map, h, control)
    ro, so = response.particular_solution(closed_loop.model_and_geometry(name)[0],
                                          v_map[:, None], w_map[None, :], h)
    np.savez(path, speed_m_s=v_map, omega_rad_s=w_map, gains=g, stable=stable,
             control_input=control, roll_amp_rad=np.abs(roll[..., k1]),
             steer_amp_rad=np.abs(steer[..., k1]), open_roll_amp_rad=np.abs(ro[..., k1]),
             open_steer_amp_rad=np.abs(so[..., k1]))
    print(f"{name} map: {len(v_map)} x {len(w_map)}, rider {control}, stable at "
          f"{int(stable.sum())} of {len(v_map)} speeds", file=sys.stderr)
