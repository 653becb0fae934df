"""Benchmark parameters of the non-linear models: benchmark, HR (hybrid), CR and CF (city).

Bicycle + rider benchmark parameters come from BicycleParameters (:mod:`.bicycle_data`); the
thesis's modifications (cranks, the city bicycle's lowered seat, Sec 2.1.1 and 3.1.1.3), the
arm loops of CF (:mod:`.arms`) and the split of the legs into separate bodies (method NP,
:mod:`.leg_bodies`) are applied here with the mass algebra of :mod:`.rigid`. Every assumption is
listed in ``data/parameters/nonlinear_models.yaml`` (:mod:`.settings`).
"""

from __future__ import annotations

from functools import cache

import numpy as np

from .. import legs, params
from . import arms, bicycle_data
from . import model as symbolic
from .leg_bodies import leg_revolution
from .numeric import moore_parameters
from .prescribed import FourierSpec
from .rigid import RigidPart, body_part, combine, subtract, with_body
from .settings import has_arms, model_spec, settings

#: Samples of one crank revolution for the leg bodies (32 harmonics kept: the four-bar motion
#: is smooth, checked in tests).
REVOLUTION_SAMPLES = 256


def _crank_axis_m(bicycle: str, rear_radius_m: float) -> np.ndarray:
    bb = settings()["bottom_bracket"][bicycle]
    return np.array([np.sqrt(bb["lcs"] ** 2 - (rear_radius_m - bb["hbb"]) ** 2), 0.0,
                     -bb["hbb"]])


def bottom_bracket_m(model: str) -> np.ndarray:
    """Crank axis A in the benchmark frame (x forward, z down, rear contact origin), m."""
    return _crank_axis_m(model_spec(model)["bicycle"], bicycle_rider(model)["rR"])


def leg_geometry(model: str) -> legs.LegGeometry:
    """The leg geometry of the model's bicycle (``legs`` and ``leg_com_model`` settings)."""
    return legs.leg_geometry(model_spec(model)["legs"],
                             settings()["assumptions"]["leg_com_model"])


def rider_drop_m(model: str, original_seat: bool = False) -> np.ndarray:
    """Displacement of the rider (benchmark frame, m) for the lowered city seat (Sec 2.1.1).

    0.05 m down along the seat tube (0.77 -> 0.72 m) on the city bicycle, zero otherwise or
    with ``original_seat`` (Fig E.1).
    """
    spec = model_spec(model)
    geom = leg_geometry(model)
    if (spec["legs"] == "city" and settings()["assumptions"]["lower_city_rider_along_seat_tube"]
            and not original_seat):
        original = params.legs()["seat_geometry"]["city"]["original_seat_tube_plus_post_m"]
        drop = original - geom.seat_tube_plus_post_m
        lam = geom.seat_tube_angle_rad
        return drop * np.array([np.cos(lam), 0.0, np.sin(lam)])
    return np.zeros(3)


@cache
def _assembled(model: str, original_seat: bool, with_arms: bool):
    """Benchmark parameters (and the arm loop, if ``with_arms``) of a model; see bicycle_rider."""
    spec = model_spec(model)
    data = bicycle_data.load(spec["bicycle"], spec["rider"])
    both = data.with_rider
    frame = body_part(data.frame, "B")
    # the rider alone = total - bicycle frame (inverse parallel-axis combination)
    rider = subtract(body_part(both, "B"), [frame])
    drop = rider_drop_m(model, original_seat)
    loop = None
    front_parts: list[RigidPart] = []
    if with_arms:
        yeadon = arms.yeadon_arms(spec["bicycle"])
        rider = subtract(rider, yeadon.segments)
        loop = arms.arm_loop(yeadon.shoulder + drop, yeadon)
        at_shoulder, at_grip = arms.fixed_parts(loop)
        front_parts = [yeadon.hand, yeadon.hand.mirrored()] + at_grip
    parts = [frame, rider.moved(drop)]
    if loop is not None:
        parts += at_shoulder
    out = dict(both)
    if settings()["assumptions"]["add_cranks"]:
        rev = leg_revolution(leg_geometry(model), _crank_axis_m(spec["bicycle"], both["rR"]),
                             both["lam"], both["rR"], 2 * np.pi, REVOLUTION_SAMPLES)
        parts += [p for name, p in zip(symbolic.LEG_BODIES, rev.mean_parts, strict=True)
                  if name.startswith("crank")]
    out = with_body(out, "B", combine(parts))
    if front_parts:
        out = with_body(out, "H", combine([body_part(out, "H")] + front_parts))
    return out, loop


@cache
def bicycle_rider(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of a model with the rider and legs lumped rigidly into body B.

    ``"benchmark"``: Meijaard et al. (2007) unchanged. ``"HR"``/``"CR"`` (and the rigid-rider
    bodies of ``"HS"``/``"CF"``): Stratos/Browser + rider Jason + two 0.2 kg cranks at the
    crank axis; on the city bicycle the rider is lowered 0.05 m along the seat tube
    (0.77 -> 0.72 m, Sec 2.1.1) unless ``original_seat`` (Fig E.1).
    """
    if model == "benchmark":
        return params.benchmark_parameters("benchmark")
    return _assembled(model, original_seat, False)[0]


@cache
def model_bodies(model: str, original_seat: bool = False) -> tuple[dict[str, float], dict]:
    """Benchmark parameters of the model's rigid bodies and the values of its arm symbols.

    Without arms: :func:`bicycle_rider` and ``{}``. With arms (CF, :mod:`.arms`): body B
    without the arms (shoulder particles added), the front frame with the hands and the grip
    particles, and the ``arm_*`` values (:data:`model.ARM_PARAMETERS`) of the arm loop at this
    seat height.
    """
    if not has_arms(model):
        return bicycle_rider(model, original_seat), {}
    bench, loop = _assembled(model, original_seat, True)
    return bench, arms.symbol_values(loop, bench, moore_parameters(bench))


@cache
def arm_loop(model: str, original_seat: bool = False) -> arms.ArmLoop:
    """The :class:`pedalrepro.nonlinear.arms.ArmLoop` of a model with arms."""
    if not has_arms(model):
        raise ValueError(f"{model} has no arm loops")
    return _assembled(model, original_seat, True)[1]


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
    (leg_params, spec, mean_parts)
        ``leg_params``: ``<body>_y``, ``<body>_m``, ``<body>_I`` for :data:`model.LEG_BODIES`;
        ``spec``: ``t -> s`` (positions, rates, accelerations in the generated ``SPEC`` order,
        a :class:`.prescribed.FourierSpec` of one revolution, ``samples`` per revolution, exact
        to rounding for the band-limited four-bar motion); ``mean_parts``: the
        revolution-averaged :class:`.rigid.RigidPart` of each body, to remove from body B.
    """
    bench = bicycle_rider(model)
    omega = float(cadence_rad_s)
    rev = leg_revolution(leg_geometry(model), bottom_bracket_m(model), bench["lam"], bench["rR"],
                         omega, samples)
    # Fourier series x(t) = sum_n Re(c_n e^{i n w t}); the crank angles also turn at -omega.
    slope = np.zeros(rev.signals.shape[0])
    slope[[3 * k + 2 for k, n in enumerate(symbolic.LEG_BODIES) if n.startswith("crank")]] = -omega
    spec = FourierSpec.from_samples(omega, rev.signals, slope, samples // 8)
    return rev.parameters, spec, rev.mean_parts


def without_legs(model: str, mean_parts, original_seat: bool = False) -> dict[str, float]:
    """Body B of :func:`model_bodies` with the revolution-averaged leg bodies removed."""
    bench = model_bodies(model, original_seat)[0]
    return with_body(bench, "B", subtract(body_part(bench, "B"), mean_parts))


def legs_fixed(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of the NT model: the legs fixed to the frame at crank angle 0.

    Thesis Sec 3.1.1.3: the models are linearised (and NT keeps the legs fixed) with the crank
    horizontal, right foot forward (``theta_A = 0``). Body B = :func:`bicycle_rider` with the
    revolution-averaged leg bodies replaced by the same bodies frozen at ``t = 0``, so that NP's
    time average and NT differ exactly by this choice of leg configuration (evaluation
    points 1a/2a: the simplified mass distribution). With arms (CF) body B and the front frame
    of :func:`model_bodies`; the arm symbols are :func:`model_bodies`' second item.
    """
    if model == "benchmark":
        return bicycle_rider(model)
    bench = model_bodies(model, original_seat)[0]
    rev = leg_revolution(leg_geometry(model), bottom_bracket_m(model), bench["lam"], bench["rR"],
                         2.0 * np.pi, REVOLUTION_SAMPLES)
    rest = without_legs(model, rev.mean_parts, original_seat)
    return with_body(rest, "B", combine([body_part(rest, "B")] + rev.frozen_parts))
