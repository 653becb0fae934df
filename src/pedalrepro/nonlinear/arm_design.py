"""The thesis's arm loops (CF and HS) as small sets of calibratable parameters (Sec 3.1.1.2,
Sec 4.2, Fig 3.3).

Thesis Sec 4.2 (discussion of CF): "the handle bar width is modelled to be the same as the
shoulder to shoulder width"; Fig 3.3b / 3.4: upright trunk, flexed arms hinged at shoulders and
elbows, ball joints at the hands. With the grip straight ahead of the shoulder the loop is
planar: the shoulder flexes about the trunk's lateral axis (SymBRiM ``FlexRotLeftShoulder``
literally) and the elbow hinges in the shoulder's sagittal plane (the branch with the elbow
below the shoulder-grip line: flexed arms, elbows down), so
:func:`pedalrepro.nonlinear.symbolic.arm_loop_elbow` holds with ``normal = (0, 1, 0)``.

:class:`ArmDesign` holds the values the loop is built from (benchmark frame, rider at the
original seat height): shoulder centre, grip (its lateral position = the shoulder's), segment
lengths, and the arms' mass as a fraction of the Yeadon arms of BicycleParameters' rider
Jason (83.5 kg). Mass distribution along each segment (three particles: proximal joint, distal
joint, COM) is Yeadon's (:func:`pedalrepro.nonlinear.arms.rod_particles`), scaled.

HS (Fig 3.3a: forward-leaning trunk, straight arms, hands on the straight bar) uses the same
joints with the grip where Yeadon's hands hold the Stratos bar (wider than the shoulders) and
the plane of each arm free: ``grip_y`` and ``elbow_dir_rad`` (the direction in which the elbow
leaves the shoulder-grip line, about that line: 0 straight down, pi/2 straight out). A truly
straight arm cannot close the loop while steering (the elbow speed per steer rate is unbounded
at full extension), so the HS arms keep a small flexion; :func:`plane_normal` turns the
direction into the shoulder's flexion axis.
"""

from __future__ import annotations

from dataclasses import astuple, dataclass, fields, replace

import numpy as np

from . import arms as _arms
from . import bicycle_data
from .rigid import RigidPart

__all__ = [
    "DESIGN_KEYS", "FREE_PLANE_KEYS", "ArmDesign", "yeadon_total_mass_kg", "nominal_design",
    "elbow_direction_rad", "plane_normal", "loop", "hands", "removed_segments", "field_names",
    "particle_steer_term",
]

#: Calibratable fields of :class:`ArmDesign` (CF: grip straight ahead of the shoulder, arms in
#: the sagittal plane), in order.
DESIGN_KEYS: tuple[str, ...] = ("shoulder_x", "shoulder_y", "shoulder_z", "grip_x", "grip_z",
                                "a", "b", "mass_scale")
#: Further calibratable fields of a design with its own grip width and arm plane (HS).
FREE_PLANE_KEYS: tuple[str, ...] = ("grip_y", "elbow_dir_rad")


@dataclass(frozen=True)
class ArmDesign:
    """Right arm of a loop (left: mirror image); lengths in m, angles in rad, benchmark frame.

    ``grip_y`` None: the grip straight ahead of the shoulder (CF); ``elbow_dir_rad`` None: the
    arm in the shoulder's sagittal plane (CF), else the elbow's direction (:func:`plane_normal`).
    """

    shoulder_x: float
    shoulder_y: float
    shoulder_z: float
    grip_x: float
    grip_z: float
    a: float
    b: float
    mass_scale: float
    sign: float = -1.0
    grip_y: float | None = None
    elbow_dir_rad: float | None = None

    def keys(self) -> tuple[str, ...]:
        """The calibratable fields of this design."""
        return DESIGN_KEYS + (FREE_PLANE_KEYS if self.elbow_dir_rad is not None else ())

    def vector(self) -> np.ndarray:
        return np.array([getattr(self, k) for k in self.keys()])

    def with_vector(self, v) -> ArmDesign:
        return replace(self, **{k: float(x) for k, x in zip(self.keys(), v, strict=True)})

    def grip(self) -> np.ndarray:
        """The right grip at steer 0 (benchmark frame)."""
        y = self.shoulder_y if self.grip_y is None else self.grip_y
        return np.array([self.grip_x, y, self.grip_z])

    def key(self) -> tuple:
        return astuple(self)


def yeadon_total_mass_kg(bicycle: str) -> float:
    """Mass of BicycleParameters' Yeadon rider Jason (with ``bicycle``'s configuration), kg."""
    data = bicycle_data.load(bicycle, rider=True)
    return float(data.with_rider["mB"] - data.frame["mB"])


def nominal_design(bicycle: str, rider_mass_kg: float, plane: str = "sagittal") -> ArmDesign:
    """Yeadon's shoulder and segment lengths, arm masses scaled to the rider's mass
    (``rider_mass_kg`` / Yeadon's total).

    ``plane`` ``"sagittal"`` (CF): the grip at Yeadon's handlebar grip (x, z) but straight ahead
    of the shoulder (grip width = shoulder width). ``"free"`` (HS): the grip where Yeadon's hand
    holds the bar and the elbow direction of Yeadon's arm (:func:`elbow_direction_rad`).
    """
    y = _arms.yeadon_arms(bicycle)
    yeadon_mass = yeadon_total_mass_kg(bicycle)
    base = ArmDesign(float(y.shoulder[0]), float(y.shoulder[1]), float(y.shoulder[2]),
                     float(y.grip[0]), float(y.grip[2]),
                     float(np.linalg.norm(y.elbow - y.shoulder)),
                     float(np.linalg.norm(y.grip - y.elbow)),
                     rider_mass_kg / yeadon_mass)
    if plane == "sagittal":
        return base
    if plane != "free":
        raise ValueError(f"arm plane {plane!r}: expected 'sagittal' or 'free' "
                         "(data/parameters/nonlinear_models.yaml, arm_plane)")
    return replace(base, grip_y=float(y.grip[1]),
                   elbow_dir_rad=elbow_direction_rad(y.shoulder, y.grip, y.elbow))


def _line_frame(shoulder: np.ndarray, grip: np.ndarray) -> tuple[np.ndarray, ...]:
    """Unit vectors along the right arm's shoulder-grip line, down and out across it."""
    u = (grip - shoulder) / np.linalg.norm(grip - shoulder)
    down = np.array([0.0, 0.0, 1.0]) - u[2] * u
    down /= np.linalg.norm(down)
    out = _arms.cross3(u, down)
    return u, down, out if out[1] > 0 else -out


def elbow_direction_rad(shoulder: np.ndarray, grip: np.ndarray, elbow: np.ndarray) -> float:
    """Direction of the elbow's offset from the shoulder-grip line, about that line: 0 straight
    down, pi/2 straight out (right arm, benchmark frame)."""
    _, down, out = _line_frame(shoulder, grip)
    off = elbow - shoulder
    return float(np.arctan2(off @ out, off @ down))


def plane_normal(shoulder: np.ndarray, grip: np.ndarray, elbow_dir_rad: float) -> np.ndarray:
    """Shoulder flexion axis of an arm whose elbow leaves the shoulder-grip line in the
    direction ``elbow_dir_rad`` (:func:`elbow_direction_rad`): the normal of the arm's plane,
    oriented so that the loop's branch ``sign = -1`` puts the elbow on that side."""
    u, down, out = _line_frame(shoulder, grip)
    e = np.cos(elbow_dir_rad) * down + np.sin(elbow_dir_rad) * out
    return _arms.cross3(e, u)


def loop(design: ArmDesign, bicycle: str, drop: np.ndarray) -> _arms.ArmLoop:
    """The right arm loop of ``design`` with the shoulder moved by ``drop`` (seat height)."""
    y = _arms.yeadon_arms(bicycle)
    s = design.mass_scale
    upper = _arms.rod_particles(y.upper, y.shoulder, y.elbow)
    fore = _arms.rod_particles(y.forearm, y.elbow, y.grip)
    shoulder = np.array([design.shoulder_x, design.shoulder_y, design.shoulder_z]) + drop
    grip = design.grip()
    normal = (np.array([0.0, 1.0, 0.0]) if design.elbow_dir_rad is None
              else plane_normal(shoulder, grip, design.elbow_dir_rad))
    out = _arms.ArmLoop(shoulder, grip, normal, design.a, design.b,
                        design.sign, (upper[0] * s, upper[1] * s, upper[2] * s, upper[3]),
                        (fore[0] * s, fore[1] * s, fore[2] * s, fore[3]))
    with np.errstate(invalid="ignore"):  # NaN elbow: the error below says why
        closes = bool(np.all(np.isfinite(out.elbow())))
    if not closes:
        raise ValueError(f"arm loop cannot close: shoulder-grip distance exceeds a + b "
                         f"({design})")
    return out


def hands(design: ArmDesign, bicycle: str) -> list[RigidPart]:
    """Both hands (Yeadon, mass-scaled) moved with the grip (CF: to the shoulder's width)."""
    y = _arms.yeadon_arms(bicycle)
    shift = design.grip() - y.grip
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
    the non-linear model's linearisation for CF's arm loops (tests/nonlinear/test_calibration.py).
    """
    p0, pp, pm = positions(0.0), positions(h), positions(-h)
    out = 0.0
    for (m, r0), (_, rp), (_, rm) in zip(p0, pp, pm, strict=True):
        out += m * (-(rp[2] - 2 * r0[2] + rm[2]) / h**2 + np.sin(lam_rad) * (rp[1] - rm[1])
                    / (2 * h))
    return float(out)
