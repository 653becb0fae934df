"""Benchmark parameters of the non-linear models: benchmark, HS, HR (hybrid), CR and CF (city).

The thesis's inputs assembled by :mod:`.assembly` (geometry and wheels read off Appendix B, the
72 kg rider, cranks and legs frozen at crank angle 0, the arm loops of CF and HS) with the
bicycle frames calibrated to Appendix B (:mod:`.calibration`); the split of the legs into
separate bodies (method NP, :mod:`.leg_bodies`) with the mass algebra of :mod:`.rigid`. Every
assumption is listed in ``data/parameters/nonlinear_models.yaml`` and ``thesis_inputs.yaml``.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from .. import params
from . import arms, calibration, symbolic
from .assembly import (
    REVOLUTION_SAMPLES,
    Assembly,
    assemble,
    assembly,
    leg_geometry,
    rider_drop_m,  # noqa: F401  (re-exported from .assembly; not part of this module's __all__)
)
from .leg_bodies import leg_revolution
from .nonlinear_model import moore_parameters
from .prescribed import FourierSpec
from .rigid import body_part, subtract, with_body
from .settings import has_arms

__all__ = [
    "bottom_bracket_m", "calibration_of", "model_assembly", "clear_caches", "bicycle_rider",
    "model_bodies", "arm_loop", "steer_limit_rad", "leg_bodies", "without_legs", "legs_fixed",
]


def bottom_bracket_m(model: str) -> np.ndarray:
    """Crank axis A in the benchmark frame (x forward, z down, rear contact origin), m."""
    return assembly(model).crank_axis


def calibration_of(model: str) -> calibration.Calibration:
    """The calibration a model uses (:func:`.calibration.calibrate`)."""
    return calibration.calibrate(model)


def model_assembly(model: str, original_seat: bool = False,
                   calibrated: bool = True) -> tuple[Assembly, dict | None]:
    """(assembly, frames) of a model: calibrated (default) or as measured (frames None)."""
    if not calibrated:
        return assembly(model, original_seat), None
    cal = calibration_of(model)
    return assembly(model, original_seat, cal.rider_shift_m, cal.arm_design), cal.frames


def clear_caches() -> None:
    """Forget the cached model bodies (after :func:`calibration.use_file` in a process that
    built models before)."""
    for fn in (bicycle_rider, model_bodies, arm_loop):
        fn.cache_clear()


@cache
def bicycle_rider(model: str, original_seat: bool = False,
                  calibrated: bool = True) -> dict[str, float]:
    """Benchmark parameters of a model with the rider, legs and cranks lumped into body B.

    ``"benchmark"``: Meijaard et al. (2007) unchanged. Otherwise :func:`.assembly.assemble`
    with the frames calibrated to Appendix B unless ``calibrated`` is False: the legs and
    cranks frozen at crank angle 0 (Sec 3.1.1.3), the city rider lowered 0.05 m unless
    ``original_seat`` (Fig E.1). With arms (CF) body B holds the shoulder particles and body H
    the hands and grip particles.
    """
    if model == "benchmark":
        return params.benchmark_parameters("benchmark")
    asm, frames = model_assembly(model, original_seat, calibrated)
    return assemble(asm, frames)


@cache
def model_bodies(model: str, original_seat: bool = False) -> tuple[dict[str, float], dict]:
    """Benchmark parameters of the model's rigid bodies and the values of its arm symbols.

    Without arms: :func:`bicycle_rider` and ``{}``. With arms (CF, :mod:`.arms`): the
    ``arm_*`` values (:data:`symbolic.ARM_PARAMETERS`) of the arm loop at this seat height.
    """
    bench = bicycle_rider(model, original_seat)
    if not has_arms(model):
        return bench, {}
    return bench, arms.symbol_values(arm_loop(model, original_seat), bench,
                                     moore_parameters(bench))


@cache
def arm_loop(model: str, original_seat: bool = False) -> arms.ArmLoop:
    """The :class:`pedalrepro.nonlinear.arms.ArmLoop` of a model with arms."""
    if not has_arms(model):
        raise ValueError(f"{model} has no arm loops")
    return model_assembly(model, original_seat)[0].loop


def steer_limit_rad(model: str, original_seat: bool = False) -> float:
    """Steer angle at which a run of the model ends like a fall (inf without arm loops).

    With arm loops: :data:`arms.STEER_REACH_FRACTION` of the steer angle at which an arm is
    fully stretched (:func:`arms.steer_reach_rad`).
    """
    if not has_arms(model):
        return float("inf")
    bench = model_bodies(model, original_seat)[0]
    return arms.STEER_REACH_FRACTION * arms.steer_reach_rad(arm_loop(model, original_seat),
                                                            bench)


def leg_bodies(model: str, cadence_rad_s: float, samples: int = REVOLUTION_SAMPLES):
    """Prescribed leg motion of a model in SymBRiM's rear-frame coordinates.

    Returns
    -------
    (leg_params, spec, frozen_parts)
        ``leg_params``: ``<body>_y``, ``<body>_m``, ``<body>_I`` for :data:`symbolic.LEG_BODIES`;
        ``spec``: ``t -> s`` (positions, rates, accelerations in the generated ``SPEC`` order,
        a :class:`.prescribed.FourierSpec` of one revolution, ``samples`` per revolution, exact
        to rounding for the band-limited four-bar motion); ``frozen_parts``: each body at crank
        angle 0 (:class:`.rigid.RigidPart`), the bodies NP removes from body B.
    """
    bench = bicycle_rider(model)
    omega = float(cadence_rad_s)
    rev = leg_revolution(leg_geometry(model), bottom_bracket_m(model), bench["lam"], bench["rR"],
                         omega, samples)
    # Fourier series x(t) = sum_n Re(c_n e^{i n w t}); the crank angles also turn at -omega.
    slope = np.zeros(rev.signals.shape[0])
    slope[[3 * k + 2 for k, n in enumerate(symbolic.LEG_BODIES) if n.startswith("crank")]] = -omega
    spec = FourierSpec.from_samples(omega, rev.signals, slope, samples // 8)
    return rev.parameters, spec, rev.frozen_parts


def without_legs(model: str, original_seat: bool = False) -> dict[str, float]:
    """Body B of :func:`model_bodies` without the six leg and crank bodies frozen at crank
    angle 0: method NP removes exactly those and adds the moving ones (:func:`leg_bodies`)."""
    bench = model_bodies(model, original_seat)[0]
    frozen = model_assembly(model, original_seat)[0].frozen
    return with_body(bench, "B", subtract(body_part(bench, "B"), frozen))


def legs_fixed(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of the NT model: the legs fixed to the frame at crank angle 0.

    Thesis Sec 3.1.1.3: the models are linearised (and NT keeps the legs fixed) with the crank
    horizontal, right foot forward (``theta_A = 0``): :func:`model_bodies`, whose body B holds
    the six leg and crank bodies frozen at ``t = 0`` and whose frames are calibrated to
    Appendix B. With arms (CF) the arm symbols are :func:`model_bodies`' second item.
    """
    return model_bodies(model, original_seat)[0]
