"""Snakemake script: particular solution on the PS grid, one npz per model (Sec 3.1.2.2.1)."""

import sys

import numpy as np

from pedalrepro import linear, momentum, response

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
ref = snakemake.params.reference
for name, path in zip(snakemake.params.models, snakemake.output.npz, strict=True):
    model = linear.linear_model(name)
    h = response.forcing(name, snakemake.params.harmonics)
    v, w = response.speed_cadence_grid(**snakemake.params.grid)
    roll, steer = response.particular_solution(model, v[:, None], w[None, :], h)
    h1 = int(np.nonzero(h.n == 1)[0][0])
    cam_roll, cam_steer = momentum.cam_amplitude(model, h)
    ref_r, ref_s = response.particular_solution(model, ref["reference_speed_m_s"],
                                                ref["reference_cadence_rpm"] * np.pi / 30, h)
    np.savez(path, speed_m_s=v, omega_rad_s=w, n=h.n, roll=roll, steer=steer,
             roll_amp_rad=np.abs(roll[..., h1]), steer_amp_rad=np.abs(steer[..., h1]),
             roll_phase_rad=np.angle(roll[..., h1]), steer_phase_rad=np.angle(steer[..., h1]),
             roll_amp_total_rad=response.superposed_amplitude(roll, h.n),
             steer_amp_total_rad=response.superposed_amplitude(steer, h.n),
             cam_roll_rad=cam_roll, cam_steer_rad=cam_steer,
             reference_roll_rad=abs(ref_r[h1]), reference_steer_rad=abs(ref_s[h1]),
             torque_roll=h.roll, torque_steer=h.steer)
    print(f"{name}: {roll.shape[0] * roll.shape[1]} points, "
          f"max roll {np.abs(roll[..., h1]).max():.4g}",
          file=sys.stderr)
