"""The calibration as pipeline outputs: tables, checks and the record (rule
``nonlinear_calibration``), and the verification with the non-linear models themselves.

Kept apart from :mod:`.calibration` (which the model bodies use) so that the verification can
build the finished models (:mod:`.models`) without an import cycle.
"""

from __future__ import annotations

import numpy as np

from .. import params
from . import bodies
from .assembly import thesis_bicycle
from .calibration import (
    NAMES,
    arm_term,
    calibrate,
    max_relative_difference,
    save,
    steer_stiffness_term,
    whipple_matrices,
)
from .models import nt_model
from .nonlinear_model import benchmark_matrices
from .settings import model_spec

__all__ = ["verify", "UNITS", "table", "checks", "arm_checks", "write_results"]


def verify(model: str) -> float:
    """Largest relative difference of the NT model's numerical linearisation from Appendix B."""
    return max_relative_difference(benchmark_matrices(nt_model(model)),
                                   params.appendix_b_model(model))


#: Units of the frame and arm parameters in the table.
UNITS = {"m": "kg", "x": "m", "z": "m", "Ixx": "kg m^2", "Izz": "kg m^2", "Ixz": "kg m^2",
         "Iyy": "kg m^2", "shoulder_x": "m", "shoulder_y": "m", "shoulder_z": "m",
         "grip_x": "m", "grip_y": "m", "grip_z": "m", "a": "m", "b": "m", "mass_scale": "-",
         "elbow_dir_rad": "rad"}


def table(models) -> list[tuple]:
    """Rows (model, body, parameter, unit, uncalibrated, calibrated) of every calibrated value.

    The frames' parameters (benchmark frame, Meijaard et al. 2007) and the rider's seat shift
    where it is an unknown.
    """
    rows = []
    for model in models:
        cal = calibrate(model)
        rows += [(m, body, key, UNITS[key], before, after)
                 for m, body, key, before, after in cal.rows()]
        rows.append((model, "rider", "seat shift", "m", 0.0, float(cal.rider_shift_m)))
        if cal.arm_design is not None:
            rows += [(model, "arms", key, UNITS[key], float(b), float(a)) for key, b, a in zip(
                cal.arm_design.keys(), cal.arm_nominal.vector(), cal.arm_design.vector(),
                strict=True)]
    return rows


def checks(models) -> list[tuple]:
    """Rows (model, check, value) for the book: metric, residuals, validity, verification."""
    out = []
    for model in models:
        cal = calibrate(model)
        uncal = whipple_matrices(bodies.bicycle_rider(model, calibrated=False))
        target = params.appendix_b_model(model)
        before = max_relative_difference({k: uncal[k] + cal.arm_contribution.get(
            k, np.zeros((2, 2))) for k in NAMES}, target)
        out += [(model, "distance", float(cal.distance)),
                (model, "max_rel_diff_uncalibrated", before),
                (model, "max_rel_diff_closed_form", float(cal.residual)),
                (model, "max_rel_diff_nonlinear", verify(model)),
                (model, "valid", float(cal.valid))]
    return out


def arm_checks(model: str) -> list[tuple]:
    """Rows (model, check, value) of a model with arm loops: Appendix B's steer stiffness term
    ``dK0[1,1]`` and that of the uncalibrated (Yeadon) arms (HS: a straight arm, singular)."""
    cal = calibrate(model)
    if cal.arm_design is None:
        return []
    target = steer_stiffness_term({"K0": params.appendix_b_model(model).K0},
                                  thesis_bicycle(model_spec(model)["bicycle"])["lam"])
    return [(model, "appendix_b_steer_stiffness_term", target),
            (model, "uncalibrated_arm_steer_stiffness_term", arm_term(model, cal.arm_nominal)),
            (model, "calibrated_arm_steer_stiffness_term",
             arm_term(model, cal.arm_design, cal.rider_shift_m))]


def write_results(models, table_csv, checks_csv, record_yaml) -> None:
    """Rule ``nonlinear_calibration``: the calibration table, its checks and the record the
    downstream rules read (:func:`use_file`)."""
    import pandas as pd

    models = [m for m in models if m != "benchmark"]
    save(record_yaml, models)
    df = pd.DataFrame(table(models), columns=["model", "body", "parameter", "unit",
                                              "uncalibrated", "calibrated"])
    df["change"] = df["calibrated"] - df["uncalibrated"]
    df["relative_change"] = df["change"] / df["uncalibrated"].abs().where(
        df["uncalibrated"] != 0)
    df.to_csv(table_csv, index=False)
    rows = checks(models) + [r for m in models for r in arm_checks(m)]
    pd.DataFrame(rows, columns=["model", "check", "value"]).to_csv(checks_csv, index=False)
