"""Snakemake script: linearise the non-linear models (Sec 3.1.1.3 verification step).

benchmark_linearisation.csv: M, C1, K0, K2 of the non-linear benchmark model (16 rows).
linearisation_vs_appendix_b.csv: the project's linearisations beside thesis Appendix B: every
model's own (HS and CF built with their arm loops).
nonlinear_checks.csv: the linearisation and energy checks as numbers for the book, including the
energy drift of unforced CF and HS runs with their arm loops and the arms' flexion and reach.
linearisation_own.npz: the matrices of every non-linear model as simulated (for PS/LA of its
own linear limit in the report).
eigen_cf_own.npz, eigen_cf_original_seat.npz: Fig E.1, the project's own CF with the 0.72 m and
the original 0.77 m seat post (eigen-sweep format of linear_eigen.py).
"""

import sys

import numpy as np
import pandas as pd
import yaml

from pedalrepro import linear, params, response
from pedalrepro.nonlinear import arms, bodies, calibration, models
from pedalrepro.nonlinear.nonlinear_model import NonlinearModel, benchmark_matrices
from pedalrepro.nonlinear.simulate import simulate

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
calibration.use_file(snakemake.input.calibration)  # frames calibrated to Appendix B
NAMES = ("M", "C1", "K0", "K2")


def rows(mats):
    return [(k, i, j, float(mats[k][i, j])) for k in NAMES for i in range(2) for j in range(2)]


meijaard = yaml.safe_load(open(snakemake.input.meijaard))
bench = benchmark_matrices(NonlinearModel(params.benchmark_parameters("benchmark")))
pd.DataFrame(rows(bench), columns=["matrix", "i", "j", "value"]).to_csv(
    snakemake.output.benchmark, index=False)



def rel_diffs(mats, ab):
    for k, i, j, value in rows(mats):
        ref = float(getattr(ab, k)[i, j])
        # Appendix B prints round-off (|x| < 1e-12) where the exact value is zero
        yield k, i, j, value, ref, abs(value - ref) / abs(ref) if abs(ref) > 1e-12 else np.nan


records, own = [], {"benchmark": bench}
for name in snakemake.params.models:
    ab = params.appendix_b_model(name)
    own[name] = benchmark_matrices(models.nt_model(name))  # what NT / NP simulate
    records += [(name, "own model", *r) for r in rel_diffs(own[name], ab)]
pd.DataFrame(records, columns=["model", "compared", "matrix", "i", "j", "project", "appendix_b",
                               "rel_diff"]).to_csv(snakemake.output.appendix_b, index=False)
# Fig E.1: the project's CF with the 0.72 m and the original 0.77 m seat post, eigenvalues on
# the linear eigen grid
speeds = response.grid(**snakemake.params.eigen_speeds)


def save_eigen(path, lin):
    e = linear.eigen_sweep(lin, speeds)
    s = linear.summarise(lin, speeds)
    np.savez(path, speed_m_s=speeds, eigenvalues=e.eigenvalues,
             names=np.array(e.names), weave_frequency_rad_s=e.weave_frequency_rad_s(),
             stable_ranges_m_s=np.array(linear.stable_ranges(lin, speeds)).reshape(-1, 2),
             weave_speed_m_s=np.nan if s.weave_speed_m_s is None else s.weave_speed_m_s,
             note=s.note, **{k: getattr(lin, k) for k in NAMES})


cf72 = own["CF"] if "CF" in own else benchmark_matrices(models.nt_model("CF"))
save_eigen(snakemake.output.eigen_cf_own, params.LinearModel(
    "CF (own, 0.72 m seat)", *(cf72[k] for k in NAMES), g=params.appendix_b_model("CF").g))
save_eigen(snakemake.output.eigen_e_1, models.original_seat_model("CF"))
# Energy check (no dissipation, rolling without slip): unforced benchmark run from a stable
# state at 5 m/s with a roll-rate perturbation, 15 s, rtol = atol = 1e-10 (DOP853).
nl = NonlinearModel(params.benchmark_parameters("benchmark"))
x0 = nl.upright_state(5.0, roll_rate_rad_s=0.5)
sim = simulate(nl, 5.0, 15.0, 20.0, x0=x0, rtol=1e-10, atol=1e-10, method="DOP853")
drift, energy = nl.energy_drift(sim.t_s, sim.states)
# the same with the arm loops moving with the steer (legs fixed), 10 s: CF, and HS if built
arm_rows = []
for name in ["CF"] + [m for m in snakemake.params.models if m == "HS"]:
    nl = models.nt_model(name)
    sim = simulate(nl, 10.0, 10.0, 20.0, x0=nl.upright_state(10.0, steer_rate_rad_s=0.02),
                   rtol=1e-10, atol=1e-10, method="DOP853")
    arm_rows.append((f"energy_relative_drift_{name}_arms", nl.energy_drift(sim.t_s, sim.states)[0],
                     f"unforced {name} with arm loops (legs fixed), 10 m/s, steer rate 0.02 rad/s, "
                     "10 s"))
    if name == "HS":  # CF's rows follow (both seats)
        design = calibration.calibrate(name).arm_design
        loop = bodies.arm_loop(name)
        elbow = loop.elbow()
        flex = np.arccos((elbow - loop.shoulder) @ (loop.grip - elbow) / loop.a / loop.b)
        arm_rows += [
            ("arm_elbow_flexion_deg_HS", float(np.degrees(flex)),
             "HS's calibrated arms: elbow flexion at steer 0"),
            ("arm_elbow_direction_deg_HS", float(np.degrees(design.elbow_dir_rad)),
             "direction of HS's elbows about the shoulder-grip line (0 down, 90 out)"),
            ("arm_steer_reach_rad_HS", arms.steer_reach_rad(loop, bodies.model_bodies(name)[0]),
             "|steer| up to which HS's arms reach the grips"),
            ("arm_steer_limit_rad_HS", float(nl.steer_limit_rad),
             "runs of HS end like a fall at this |steer|")]
cf = models.nt_model("CF")
design = calibration.calibrate("CF").arm_design
flexion = {seat: calibration.elbow_flexion_rad(design, "CF", seat) for seat in (False, True)}
reach = {seat: arms.steer_reach_rad(bodies.arm_loop("CF", seat),
                                   bodies.model_bodies("CF", seat)[0])
         for seat in (False, True)}
pd.DataFrame([
    ("benchmark_linearisation_max_abs_diff", max(
        abs(v - meijaard[k][i][j]) for k, i, j, v in rows(bench)), "Meijaard 2007, 16 entries"),
    ("energy_relative_drift", drift, "unforced benchmark, 5 m/s, roll rate 0.5 rad/s, 15 s"),
    ("energy_J", float(energy[0]), "total mechanical energy of that run"),
    ("arm_elbow_flexion_deg", float(np.degrees(flexion[False])),
     "CF's calibrated arms: elbow flexion at steer 0, 0.72 m seat"),
    ("arm_elbow_flexion_original_seat_deg", float(np.degrees(flexion[True])),
     "the same at the original 0.77 m seat (at least Yeadon's measured pose)"),
    ("arm_steer_reach_rad", reach[False], "|steer| up to which CF's arms reach the grips, 0.72 m"),
    ("arm_steer_reach_original_seat_rad", reach[True], "the same at the original 0.77 m seat"),
    ("arm_steer_limit_rad", float(cf.steer_limit_rad),
     "runs of CF end like a fall at this |steer| (arms.STEER_REACH_FRACTION of the reach)"),
] + arm_rows + [
    (f"appendix_b_max_rel_diff_{m}", float(np.nanmax([r[7] for r in records if r[0] == m])),
     "largest relative difference of the 16 entries (exact zeros excluded)")
     for m in snakemake.params.models],
    columns=["check", "value", "what"]).to_csv(
    snakemake.output.checks, index=False)
np.savez(snakemake.output.own, **{f"{m}_{k}": v[k] for m, v in own.items() for k in NAMES})
print("benchmark and", list(snakemake.params.models), "linearised", file=sys.stderr)
