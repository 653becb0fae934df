"""The non-linear thesis models ready to integrate: NT (legs fixed) and NP (legs prescribed).

Each model is a :class:`.nonlinear_model.NonlinearModel` built from the bodies of
:mod:`.bodies`, with the arm loops of CF and HS (:mod:`.arms`, :mod:`.arm_design`).
"""

from __future__ import annotations

from .. import params
from . import bodies
from .nonlinear_model import NonlinearModel, benchmark_matrices
from .settings import model_options, model_spec

__all__ = ["nt_model", "np_model", "original_seat_model"]


def nt_model(name: str, original_seat: bool = False) -> NonlinearModel:
    """The NT model: the legs fixed to the frame at crank angle 0 (Sec 3.1.1.3).

    CF and HS carry their arm loops (:mod:`pedalrepro.nonlinear.arms`). ``original_seat``:
    the city rider at the original 0.77 m seat (Fig E.1).
    """
    return NonlinearModel(bodies.legs_fixed(name, original_seat), model_options(name),
                          arm_parameters=bodies.model_bodies(name, original_seat)[1],
                          steer_limit_rad=bodies.steer_limit_rad(name, original_seat))


def np_model(name: str, cadence_rad_s: float) -> NonlinearModel:
    """The NP model at one cadence: legs and cranks as bodies with prescribed motion.

    Body B is the NT body without exactly the six bodies frozen at crank angle 0
    (:func:`.bodies.without_legs`); the moving ones are added.
    """
    leg_params, spec, _ = bodies.leg_bodies(name, cadence_rad_s)
    return NonlinearModel(bodies.without_legs(name), model_options(name, legs=True),
                          leg_params, spec,
                          arm_parameters=bodies.model_bodies(name)[1],
                          steer_limit_rad=bodies.steer_limit_rad(name))


def original_seat_model(model: str = "CF") -> params.LinearModel:
    """Fig E.1: CF with the original 0.77 m seat tube + post (Sec 3.2.1, Appendix E).

    The project's calibrated CF linearised (legs fixed at crank angle 0, as the NT model) with
    the rider without arms, shoulders included, *not* lowered: the hands stay on the handlebar,
    so the arm loop closes with a more extended elbow than at the 0.72 m seat.
    """
    if model == "benchmark" or model_spec(model)["legs"] != "city":
        raise ValueError(f"{model}: the seat was lowered on the city bicycle only (Sec 2.1.1)")
    nl = nt_model(model, original_seat=True)
    mats = benchmark_matrices(nl)
    return params.LinearModel(f"{model} (0.77 m seat)", *(mats[k] for k in
                                                          ("M", "C1", "K0", "K2")),
                              g=nl.bench["g"])
