"""The thesis's inputs assembled into the non-linear models' rigid bodies, before calibration.

Thesis Sec 3.1.1.3: "the bicycles and anthropomorphic parameters as in Schwab et al. (2012)".
The geometry and wheel data the thesis used are read off Appendix B
(``data/parameters/thesis_inputs.yaml``, :func:`thesis_bicycle`); the rider is the 72 kg rider
of Moore et al. (2009) (:func:`thesis_rider`); cranks and legs are frozen at crank angle 0
(:mod:`.leg_bodies`); CF's arms are the loops of :mod:`.arm_design`. An :class:`Assembly` keeps
the bicycle's measured frames apart from what is rigidly attached to them, so that
:mod:`.calibration` can change the frames alone and :func:`assemble` builds the benchmark
parameters of any frames.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from .. import legs, params, paths
from . import arm_design, arms, bicycle_data, symbolic
from .leg_bodies import leg_revolution
from .rigid import RigidPart, body_part, combine, parallel_axis, subtract, with_body
from .settings import has_arms, model_spec, settings, thesis_inputs

__all__ = [
    "REVOLUTION_SAMPLES", "thesis_bicycle", "thesis_rider", "leg_geometry", "crank_axis_m",
    "seat_tube_unit", "rider_drop_m", "Assembly", "assembly", "assemble",
]

#: Samples of one crank revolution for the leg bodies (32 harmonics kept: the four-bar motion
#: is smooth, checked in tests).
REVOLUTION_SAMPLES = 256


@cache
def thesis_bicycle(bicycle: str) -> dict[str, float]:
    """Bicycle-only benchmark parameters with the thesis's geometry and wheels.

    BicycleParameters' values (:func:`.bicycle_data.load`) with the steer-axis tilt, trail,
    wheelbase, wheel radii and wheel spin inertias of ``thesis_inputs.yaml`` (rounded tabulated
    values, read off Appendix B's Whipple identities). Other bicycles: unchanged.
    """
    alone = dict(bicycle_data.load(bicycle, rider=False).frame)
    table = thesis_inputs()["bicycles"]
    if bicycle not in table:
        return alone
    row = table[bicycle]
    for key in ("lam_deg", "c", "w", "rR", "IRyy", "rF", "IFyy"):
        if key not in row:
            raise KeyError(f"data/parameters/thesis_inputs.yaml: bicycles.{bicycle}.{key} missing")
    alone.update({k: float(row[k]) for k in ("c", "w", "rR", "IRyy", "rF", "IFyy")})
    alone["lam"] = float(np.deg2rad(row["lam_deg"]))
    return alone


def _moments(part: RigidPart) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, first moment m r, second moment about the origin) of a part."""
    return part.mass, part.mass * part.com, part.inertia + parallel_axis(part.mass, part.com)


def _from_moments(m: float, first: np.ndarray, second: np.ndarray) -> RigidPart:
    com = first / m
    return RigidPart(m, com, second - parallel_axis(m, com))


@cache
def thesis_rider(bicycle: str) -> RigidPart:
    """The thesis's 72 kg rigid rider on ``bicycle`` (seat as built).

    Browser: the benchmark-form rider of Moore et al. (2009), BicycleParameters
    ``JasonBrowserBenchmark.txt`` (``rider_jason.yaml``). Other bicycles (ASSUMPTION,
    ``thesis_inputs.yaml``): that rider plus the change of posture between BicycleParameters'
    two Yeadon configurations, scaled to the benchmark rider's mass.
    """
    spec = thesis_inputs()["rider"]
    ref = params.read_yaml(paths.PARAMETERS / "rider_jason.yaml")[spec["benchmark_rider"]]
    base = body_part({k: float(v) for k, v in ref.items()}, "B")
    home = spec["benchmark_rider_bicycle"]
    if bicycle == home:
        return base
    yeadon = {}
    for bike in (home, bicycle):
        data = bicycle_data.load(bike, rider=True)
        yeadon[bike] = _moments(subtract(body_part(data.with_rider, "B"),
                                         [body_part(data.frame, "B")]))
    scale = base.mass / yeadon[home][0]
    m, first, second = _moments(base)
    return _from_moments(m, first + scale * (yeadon[bicycle][1] - yeadon[home][1]),
                         second + scale * (yeadon[bicycle][2] - yeadon[home][2]))


def leg_geometry(model: str) -> legs.LegGeometry:
    """The leg geometry of the model's bicycle (``legs`` and ``leg_com_model`` settings)."""
    return legs.leg_geometry(model_spec(model)["legs"],
                             settings()["assumptions"]["leg_com_model"])


def crank_axis_m(bicycle: str, rear_radius_m: float) -> np.ndarray:
    """Crank axis A in the benchmark frame (x forward, z down, rear contact origin), m."""
    bb = settings()["bottom_bracket"][bicycle]
    return np.array([np.sqrt(bb["lcs"] ** 2 - (rear_radius_m - bb["hbb"]) ** 2), 0.0,
                     -bb["hbb"]])


def seat_tube_unit(model: str) -> np.ndarray:
    """Unit vector down the seat tube (benchmark frame: forward and down), the seat's travel."""
    lam = leg_geometry(model).seat_tube_angle_rad
    return np.array([np.cos(lam), 0.0, np.sin(lam)])


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
        return (original - geom.seat_tube_plus_post_m) * seat_tube_unit(model)
    return np.zeros(3)


@dataclass(frozen=True)
class Assembly:
    """A model before calibration: the bicycle and what is rigidly attached to its frames.

    ``bicycle``: bicycle-only benchmark parameters (thesis geometry and wheels; frames B and H
    as measured); ``rear_parts``: rider (without moving arms), legs and cranks frozen at crank
    angle 0, shoulder particles; ``front_parts``: hands and grip particles (CF); ``frozen``:
    the six leg and crank bodies at crank angle 0 (removed again for NP); ``loop``: the arm
    loop or None; ``crank_axis``: crank axis A (benchmark frame).
    """

    bicycle: dict
    rear_parts: tuple
    front_parts: tuple
    frozen: tuple
    loop: arms.ArmLoop | None
    crank_axis: np.ndarray


@cache
def assembly(model: str, original_seat: bool = False, rider_shift_m: float = 0.0,
             design: arm_design.ArmDesign | None = None) -> Assembly:
    """The uncalibrated parts of ``model`` (see :class:`Assembly`), thesis Sec 3.1.1.3.

    Rider: :func:`thesis_rider`, lowered 0.05 m along the seat tube on the city bicycle unless
    ``original_seat`` (Sec 2.1.1), and moved a further ``rider_shift_m`` down the seat tube (the
    Stratos rider's seat position is a calibration unknown). Its legs are taken out with their
    revolution-averaged mass distribution (the rider file's legs are in no particular crank
    position) and the six leg and crank bodies (0.2 kg cranks, Table D.1) are added frozen at
    crank angle 0 (crank horizontal, right foot forward), the configuration the thesis
    linearised. With arms (CF): the arm segments are taken out of the rider and replaced by the
    loops of ``design`` (default: :func:`arm_design.nominal_design`).
    """
    spec = model_spec(model)
    bike = thesis_bicycle(spec["bicycle"])
    drop = rider_drop_m(model, original_seat) + rider_shift_m * seat_tube_unit(model)
    rider_mass = thesis_rider(spec["bicycle"]).mass
    rider = thesis_rider(spec["bicycle"]).moved(drop)
    axis = crank_axis_m(spec["bicycle"], bike["rR"])
    rev = leg_revolution(leg_geometry(model), axis, bike["lam"], bike["rR"], 2 * np.pi,
                         REVOLUTION_SAMPLES)
    rider_legs = [p.moved(drop) for name, p in zip(symbolic.LEG_BODIES, rev.mean_parts,
                                                    strict=True) if not name.startswith("crank")]
    rider = subtract(rider, rider_legs)
    frozen = list(rev.frozen_parts)
    if not settings()["assumptions"]["add_cranks"]:
        frozen = [p for name, p in zip(symbolic.LEG_BODIES, frozen, strict=True)
                  if not name.startswith("crank")]
    rear: list[RigidPart] = [rider, *frozen]
    front: list[RigidPart] = []
    loop = None
    if has_arms(model):
        if design is None:
            design = arm_design.nominal_design(spec["bicycle"], rider_mass)
        rear[0] = subtract(rear[0], arm_design.removed_segments(spec["bicycle"], rider_mass,
                                                                 drop))
        loop = arm_design.loop(design, spec["bicycle"], drop)
        at_shoulder, at_grip = arms.fixed_parts(loop)
        front += arm_design.hands(design, spec["bicycle"]) + list(at_grip)
        rear += list(at_shoulder)
    return Assembly(bike, tuple(rear), tuple(front), tuple(frozen), loop, axis)


def assemble(asm: Assembly, frames: dict | None = None) -> dict[str, float]:
    """Benchmark parameters of an assembly with the frames ``frames`` (default: measured).

    ``frames``: ``{"B": RigidPart, "H": RigidPart}`` (the bicycle's rear and front frame);
    body B = rear frame + ``rear_parts``, body H = front frame + ``front_parts``.
    """
    bike = asm.bicycle
    frames = frames or {}
    rear = frames.get("B", body_part(bike, "B"))
    front = frames.get("H", body_part(bike, "H"))
    out = with_body(bike, "B", combine([rear, *asm.rear_parts]))
    if asm.front_parts:
        front = combine([front, *asm.front_parts])
    return with_body(out, "H", front)
