"""The thesis's CF arm geometry as a small set of calibratable parameters (Sec 3.1.1.2, Sec 4.2).

Thesis Sec 4.2 (discussion of CF): "the handle bar width is modelled to be the same as the
shoulder to shoulder width"; Fig 3.3b / 3.4: upright trunk, flexed arms hinged at shoulders and
elbows, ball joints at the hands. With the grip straight ahead of the shoulder the loop is
planar: the shoulder flexes about the trunk's lateral axis (SymBRiM ``FlexRotLeftShoulder``
literally) and the elbow hinges in the shoulder's sagittal plane (the branch with the elbow
below the shoulder-grip line: flexed arms, elbows down), so
:func:`pedalrepro.nonlinear.model.arm_loop_elbow` holds with ``normal = (0, 1, 0)``.

:class:`ArmDesign` holds the values the loop is built from (benchmark frame, rider at the
original seat height): shoulder centre, grip (its lateral position = the shoulder's), segment
lengths, and the arms' mass as a fraction of the Yeadon arms of BicycleParameters' rider
Jason (83.5 kg). Mass distribution along each segment (three particles: proximal joint, distal
joint, COM) is Yeadon's (:func:`pedalrepro.nonlinear.arms.rod_particles`), scaled.
"""

from __future__ import annotations

from dataclasses import astuple, dataclass, fields, replace

import numpy as np

from . import arms as _arms
from . import bicycle_data
from .rigid import RigidPart

#: Calibratable fields of :class:`ArmDesign`, in order.
DESIGN_KEYS: tuple[str, ...] = ("shoulder_x", "shoulder_y", "shoulder_z", "grip_x", "grip_z",
                                "a", "b", "mass_scale")


@dataclass(frozen=True)
class ArmDesign:
    """Right arm of the CF loop (left: mirror image); lengths in m, benchmark frame."""

    shoulder_x: float
    shoulder_y: float
    shoulder_z: float
    grip_x: float
    grip_z: float
    a: float
    b: float
    mass_scale: float
    sign: float = -1.0

    def vector(self) -> np.ndarray:
        return np.array([getattr(self, k) for k in DESIGN_KEYS])

    def with_vector(self, v) -> ArmDesign:
        return replace(self, **{k: float(x) for k, x in zip(DESIGN_KEYS, v, strict=True)})

    def key(self) -> tuple:
        return astuple(self)


def yeadon_total_mass_kg(bicycle: str) -> float:
    """Mass of BicycleParameters' Yeadon rider Jason (with ``bicycle``'s configuration), kg."""
    data = bicycle_data.load(bicycle, rider=True)
    return float(data.with_rider["mB"] - data.frame["mB"])


def nominal_design(bicycle: str, rider_mass_kg: float) -> ArmDesign:
    """Yeadon's shoulder and segment lengths; the grip at Yeadon's handlebar grip (x, z) but
    straight ahead of the shoulder (grip width = shoulder width); arm masses scaled to the
    rider's mass (``rider_mass_kg`` / Yeadon's total)."""
    y = _arms.yeadon_arms(bicycle)
    yeadon_mass = yeadon_total_mass_kg(bicycle)
    return ArmDesign(float(y.shoulder[0]), float(y.shoulder[1]), float(y.shoulder[2]),
                     float(y.grip[0]), float(y.grip[2]),
                     float(np.linalg.norm(y.elbow - y.shoulder)),
                     float(np.linalg.norm(y.grip - y.elbow)),
                     rider_mass_kg / yeadon_mass)


def loop(design: ArmDesign, bicycle: str, drop: np.ndarray) -> _arms.ArmLoop:
    """The right arm loop of ``design`` with the shoulder moved by ``drop`` (seat height)."""
    y = _arms.yeadon_arms(bicycle)
    s = design.mass_scale
    upper = _arms.rod_particles(y.upper, y.shoulder, y.elbow)
    fore = _arms.rod_particles(y.forearm, y.elbow, y.grip)
    shoulder = np.array([design.shoulder_x, design.shoulder_y, design.shoulder_z]) + drop
    grip = np.array([design.grip_x, design.shoulder_y, design.grip_z])
    out = _arms.ArmLoop(shoulder, grip, np.array([0.0, 1.0, 0.0]), design.a, design.b,
                        design.sign, (upper[0] * s, upper[1] * s, upper[2] * s, upper[3]),
                        (fore[0] * s, fore[1] * s, fore[2] * s, fore[3]))
    if not np.all(np.isfinite(out.elbow())):
        raise ValueError(f"arm loop cannot close: shoulder-grip distance exceeds a + b "
                         f"({design})")
    return out


def hands(design: ArmDesign, bicycle: str) -> list[RigidPart]:
    """Both hands (Yeadon, mass-scaled) moved with the grip to the shoulder's width."""
    y = _arms.yeadon_arms(bicycle)
    shift = np.array([design.grip_x, design.shoulder_y, design.grip_z]) - y.grip
    hand = RigidPart(y.hand.mass * design.mass_scale, y.hand.com + shift,
                     y.hand.inertia * design.mass_scale)
    return [hand, hand.mirrored()]


def removed_segments(bicycle: str, rider_mass_kg: float, drop: np.ndarray) -> list[RigidPart]:
    """The four Yeadon arm segments (hands included) at their pose, scaled to the rider's mass:
    what the rigid rider loses when its arms become loops."""
    y = _arms.yeadon_arms(bicycle)
    s = rider_mass_kg / yeadon_total_mass_kg(bicycle)
    return [RigidPart(p.mass * s, p.com + drop, p.inertia * s) for p in y.segments]


def field_names() -> tuple[str, ...]:
    return tuple(f.name for f in fields(ArmDesign))


def particle_steer_term(positions, lam_rad: float, h: float = 1e-4) -> float:
    """``dK0[1,1]`` of particles whose benchmark-frame positions follow the steer angle.

    ``positions(delta) -> [(mass, r), ...]`` with the rear frame upright. For a point fixed in
    the rear or front frame ``K0[1,1] - K0[0,1] sin(lam)`` vanishes (Meijaard et al. 2007); a
    particle moving relative to both adds ``m (-z'' + sin(lam) y')`` (z down, derivatives with
    respect to the steer angle at zero steer; central differences, error ~h^2). Checked against
    the non-linear model's linearisation for CF's arm loops (tests/test_calibration.py).
    """
    p0, pp, pm = positions(0.0), positions(h), positions(-h)
    out = 0.0
    for (m, r0), (_, rp), (_, rm) in zip(p0, pp, pm, strict=True):
        out += m * (-(rp[2] - 2 * r0[2] + rm[2]) / h**2 + np.sin(lam_rad) * (rp[1] - rm[1])
                    / (2 * h))
    return float(out)


def straight_arm_particles(kind: str, shoulder: np.ndarray, grip: np.ndarray,
                           parts: list[tuple[float, float]], bench: dict):
    """Positions of a straight (rigid) arm pair for a steer angle: ``kind`` ``"hand_slides"``
    (ball joint at the shoulder; the hand slides along the straight bar, i.e. the steered
    lateral axis, so that the shoulder-hand distance stays), or ``"shoulder_slides"`` (ball
    joint at the hand; the arm slides through a ball joint at the shoulder: shoulder-girdle
    protraction/retraction). ``parts``: (mass, distance from the shoulder as a fraction of the
    nominal shoulder-grip length) of the arm's particles. Neither adds a degree of freedom."""
    length = float(np.linalg.norm(grip - shoulder))
    hub = np.array([bench["w"] + bench["c"], 0.0, 0.0])

    def positions(delta: float):
        out = []
        for side in (1.0, -1.0):
            mirror = np.array([1.0, side, 1.0])
            s, h0 = shoulder * mirror, grip * mirror
            h = _arms.grip_at_steer(h0, delta, bench)
            if kind == "hand_slides":
                e = _arms.grip_at_steer(hub + [0.0, 1.0, 0.0], delta, bench) - hub
                d = h - s
                b, c = d @ e, d @ d - length**2
                roots = (-b + np.sqrt(b * b - c), -b - np.sqrt(b * b - c))
                h = h + min(roots, key=abs) * e
                out += [(m, s + f * (h - s)) for m, f in parts]
            elif kind == "shoulder_slides":
                u = (s - h) / np.linalg.norm(s - h)
                out += [(m, h + (1.0 - f) * length * u) for m, f in parts]
            else:
                raise ValueError(f"unknown straight-arm layout {kind!r}")
        return out

    return positions
