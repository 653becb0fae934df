"""Arm loops of the city posture (model CF, thesis Sec 3.1.1.2-3.1.1.3, Fig 3.4).

Schwab, Meijaard & Kooijman (2012), the thesis's source for CF: "the upper body is upright and
stays fixed with respect to the rear frame and the arms, hinged at the shoulders and the
elbows, exert the control force on the handlebar"; Fig 3.4: hinges at shoulders and elbows,
ball-and-socket joints at the hands. Neither adds degrees of freedom. Here:

* The rider is BicycleParameters' Yeadon human of rider Jason on the Browser
  (``add_rider('Jason', reCalc=True)``); the four arm segments (``A1``, ``A2``, ``B1``, ``B2``)
  are taken out of the rigid rider (body B).
* The hands (the Yeadon solids from the wrist to the finger tips, ``a4``-``a6``) are lumped
  into the front frame (handlebar) in their nominal pose; the grip point ``H`` is the base of
  the thumb, the point BicycleParameters puts on the handlebar ends (``w_hb / 2`` apart).
* Each arm is an upper arm ``S -> E`` (length ``a``, Yeadon ``A1``/``B1``) and a forearm
  ``E -> H`` (length ``b`` = elbow to base of thumb; mass, COM and inertia of the forearm
  solids ``a2``, ``a3``). Joints as SymBRiM's ``FlexRotLeftShoulder`` +
  ``PinElbowStickLeftArm`` + ``HolonomicHandGrips``: the upper arm stays in a plane through the
  shoulder, the elbow follows in closed form from the steer angle
  (:func:`pedalrepro.nonlinear.symbolic.arm_loop_elbow`).
* Each segment is a rod of three particles with its mass, COM and transverse central inertia
  (``m1 = I / (c l)`` at the proximal joint, ``m2 = I / ((l - c) l)`` at the distal joint,
  ``m3 = m - m1 - m2`` at the COM, ``c`` the COM distance from the proximal joint). The
  inertia about the segment's own axis is neglected (Yeadon: 1.4e-3 kg m^2 for the forearm-hand,
  5 % of the transverse value), as is the difference of its two transverse moments (mean used).
* The Yeadon posture has the elbows 0.047 m outside the shoulders' sagittal planes (shoulder
  adduction ``CA1adduction`` = -0.16 rad) and the arm nearly straight (elbow 14 deg), so a
  shoulder flexing about the trunk's lateral axis cannot close that loop (6.9 mm short). The
  flexion axis is therefore the lateral axis tilted by the fixed adduction
  (:func:`flexion_axis`): the loop then closes on Yeadon's posture exactly
  (:func:`nominal_posture`), and the upper arm moves in the plane of Yeadon's upper arm.
* City seat (0.77 -> 0.72 m, Sec 2.1.1): the rider without the arms (shoulders included) is
  lowered along the seat tube; the hands stay on the handlebar, so the arm posture changes.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from . import bicycle_data, symbolic
from .rigid import RigidPart, combine, point_mass

__all__ = [
    "YeadonArms", "yeadon_arms", "rod_particles", "ArmLoop", "cross3", "grip_at_steer",
    "flexion_axis",
    "arm_loop", "moving_particles", "STEER_REACH_FRACTION", "steer_reach_rad", "closure_margin_m2",
    "fixed_parts", "symbol_values", "nominal_posture",
]


@dataclass(frozen=True)
class YeadonArms:
    """The right arm of the Yeadon rider in the benchmark frame (original seat height).

    ``shoulder``, ``elbow``, ``grip``: joint centres and the base of the thumb; ``upper``,
    ``forearm``, ``hand``: the parts; ``segments``: the four Yeadon arm segments (both arms) as
    they sit in BicycleParameters' rigid rider.
    """

    shoulder: np.ndarray
    elbow: np.ndarray
    grip: np.ndarray
    upper: RigidPart
    forearm: RigidPart
    hand: RigidPart
    segments: tuple[RigidPart, ...]


@cache
def yeadon_arms(bicycle: str = "Browser") -> YeadonArms:
    """Arm geometry and inertia of rider Jason on ``bicycle`` from BicycleParameters/Yeadon
    (the points and parts of :func:`.bicycle_data.load`, in the benchmark frame)."""
    arms = bicycle_data.load(bicycle, rider=True).arms
    pts = {k: np.asarray(v, float) for k, v in arms["points"].items()}

    def part(name: str) -> RigidPart:
        p = arms["parts"][name]
        return RigidPart(float(p["mass"]), np.asarray(p["com"], float),
                         np.asarray(p["inertia"], float))

    # B = right arm (bicycle y > 0); yeadon solid order: b2, b3 forearm; b4, b5, b6 hand
    # (wrist -> base of thumb -> knuckles -> finger tips); b4's pos is the base of the thumb.
    forearm = combine(part(s) for s in ("b2", "b3"))
    hand = combine(part(s) for s in ("b4", "b5", "b6"))
    return YeadonArms(pts["shoulder"], pts["elbow"], pts["grip"], part("B1"), forearm, hand,
                      tuple(part(s) for s in ("A1", "A2", "B1", "B2")))


def rod_particles(part: RigidPart, start: np.ndarray, end: np.ndarray) -> tuple[float, float, float,
                                                                           float]:
    """Three particles of a rod ``start -> end`` with the part's mass, COM, transverse inertia.

    Returns ``(m_start, m_end, m_com, c / l)``. The COM is projected on the axis (Yeadon's
    segments are coaxial stacks of solids: it lies on it) and the transverse inertia is the
    mean of the two central moments across the axis.
    """
    axis = end - start
    length = float(np.linalg.norm(axis))
    e = axis / length
    c = float((part.com - start) @ e)
    i_axial = float(e @ part.inertia @ e)
    i_perp = (float(np.trace(part.inertia)) - i_axial) / 2.0
    m1 = i_perp / (c * length)
    m2 = i_perp / ((length - c) * length)
    m3 = part.mass - m1 - m2
    if not (0 < c < length) or m3 < 0:
        raise ValueError(f"rod particles: COM at {c} of {length} m, centre mass {m3} kg < 0")
    return m1, m2, m3, c / length


@dataclass(frozen=True)
class ArmLoop:
    """One arm loop in the benchmark frame: shoulder, grip (steer 0), lengths, branch, rods."""

    shoulder: np.ndarray
    grip: np.ndarray
    normal: np.ndarray
    a: float
    b: float
    sign: float
    upper: tuple[float, float, float, float]
    forearm: tuple[float, float, float, float]

    def elbow(self, grip: np.ndarray | None = None) -> np.ndarray:
        """Closed-form elbow (benchmark frame; the plane ``y = S_y`` is the same as Moore's)."""
        h = self.grip if grip is None else grip
        return np.array(symbolic.arm_loop_elbow(self.shoulder, h, self.normal, self.a, self.b,
                                              self.sign, sqrt=np.sqrt))

    def mirrored(self) -> ArmLoop:
        """The left arm: reflected in the bicycle's plane of symmetry, flexion axis ``-M n``."""
        m = np.array([1.0, -1.0, 1.0])
        return ArmLoop(self.shoulder * m, self.grip * m, -self.normal * m, self.a, self.b,
                       self.sign, self.upper, self.forearm)


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a x b`` of two 3-vectors: the same products and differences as ``numpy.cross`` (so the
    same bits), without its axis handling, which took 58 us a call, a quarter of the model HS's
    calibration (:mod:`pedalrepro.nonlinear.calibration` calls it 3e5 times)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def grip_at_steer(grip: np.ndarray, steer_rad: float, bench: dict) -> np.ndarray:
    """The grip point rotated by the steer angle about the steer axis (Rodrigues; benchmark
    frame, rear frame upright: the axis through ``(w + c, 0, 0)`` along
    ``(sin lam, 0, cos lam)``, positive steer to the right as Meijaard et al. 2007)."""
    k = np.array([np.sin(bench["lam"]), 0.0, np.cos(bench["lam"])])
    origin = np.array([bench["w"] + bench["c"], 0.0, 0.0])
    r = grip - origin
    c, s = np.cos(steer_rad), np.sin(steer_rad)
    return origin + r * c + cross3(k, r) * s + k * (k @ r) * (1 - c)


def flexion_axis(arms: YeadonArms | None = None, sagittal: bool = False) -> np.ndarray:
    """Shoulder flexion axis (unit, benchmark frame, fixed in the trunk).

    ``sagittal``: the trunk's lateral axis ``(0, 1, 0)`` (SymBRiM's ``FlexRotLeftShoulder``
    literally: the upper arm stays in the sagittal plane through the shoulder). Default: the
    unit vector nearest the lateral axis that is perpendicular to Yeadon's upper arm, i.e. the
    lateral axis tilted by Yeadon's (fixed) shoulder adduction, so that the nominal posture
    closes the loop exactly. The sagittal plane cannot close the loop at the original 0.77 m
    seat: Yeadon's arm is almost straight (elbow 14 deg) with the elbow 0.047 m outside the
    shoulder's sagittal plane (:func:`nominal_posture`).
    """
    if sagittal:
        return np.array([0.0, 1.0, 0.0])
    y = yeadon_arms() if arms is None else arms
    u = (y.elbow - y.shoulder) / np.linalg.norm(y.elbow - y.shoulder)
    n = np.array([0.0, 1.0, 0.0]) - u[1] * u
    return n / np.linalg.norm(n)


def arm_loop(shoulder: np.ndarray, arms: YeadonArms | None = None,
             sagittal: bool = False) -> ArmLoop:
    """The right arm loop with the shoulder at ``shoulder`` (grip, lengths from Yeadon).

    The elbow branch is the one nearest Yeadon's elbow.
    """
    y = yeadon_arms() if arms is None else arms
    a = float(np.linalg.norm(y.elbow - y.shoulder))
    b = float(np.linalg.norm(y.grip - y.elbow))
    n = flexion_axis(y, sagittal)
    upper = rod_particles(y.upper, y.shoulder, y.elbow)
    forearm = rod_particles(y.forearm, y.elbow, y.grip)
    best = None
    for sign in (1.0, -1.0):
        trial = ArmLoop(shoulder, y.grip, n, a, b, sign, upper, forearm)
        e = trial.elbow()
        if not np.all(np.isfinite(e)):
            raise ValueError("arm loop cannot close: shoulder too far from the grip")
        dist = float(np.linalg.norm(e - y.elbow))
        if best is None or dist < best[0]:
            best = (dist, trial)
    return best[1]


def moving_particles(loop: ArmLoop, steer_rad: float, bench: dict):
    """Masses and benchmark-frame positions of the three moving particles of both arms
    (elbow, upper-arm COM, forearm COM; right arm first) at steer angle ``steer_rad``."""
    out = []
    for arm in (loop, loop.mirrored()):
        h = grip_at_steer(arm.grip, steer_rad, bench)
        s = arm.shoulder
        e = arm.elbow(h)
        mu1, mu2, mu3, cu = arm.upper
        mf1, mf2, mf3, cf = arm.forearm
        out += [(mu2 + mf1, e), (mu3, s + cu * (e - s)), (mf3, e + cf * (h - e))]
    return out


#: Runs of a model with arm loops end (like a fall) at this fraction of the steer angle at which
#: the outer arm is fully stretched: near full stretch the elbow speed per steer rate grows
#: without bound (ASSUMPTION, data/parameters/nonlinear_models.yaml).
STEER_REACH_FRACTION = 0.95


def steer_reach_rad(loop: ArmLoop, bench: dict) -> float:
    """Largest ``|steer|`` (rad) at which both arms still reach the grips (bisection, 1e-12)."""

    def closes(delta: float) -> bool:
        with np.errstate(invalid="ignore"):  # sqrt of a negative number: the loop is open
            return all(np.all(np.isfinite(arm.elbow(grip_at_steer(arm.grip, sgn * delta, bench))))
                       for arm in (loop, loop.mirrored()) for sgn in (1.0, -1.0))

    if not closes(0.0):
        raise ValueError("arm loop does not close at zero steer")
    lo, hi = 0.0, np.pi / 2
    if closes(hi):
        return hi
    while hi - lo > 1e-12:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if closes(mid) else (lo, mid)
    return lo


def closure_margin_m2(loop: ArmLoop, steer_rad: float, bench: dict) -> float:
    """How far both arms are from losing their grips at steer ``+-steer_rad`` (m^2): the least
    of ``a^2 - t^2`` (squared distance of the elbow from the shoulder-grip chord, ``t`` the
    elbow's position along it, :func:`symbolic.arm_loop_elbow`) and ``b^2 - dy^2`` over both arms
    and both signs; negative when a loop is open. A smooth stand-in for
    :func:`steer_reach_rad` ``>= steer_rad`` (the loop closes at every smaller steer angle)."""
    out = np.inf
    for arm in (loop, loop.mirrored()):
        for sgn in (1.0, -1.0):
            r = grip_at_steer(arm.grip, sgn * steer_rad, bench) - arm.shoulder
            dy = float(arm.normal @ r)
            rp = r - dy * arm.normal
            d = float(np.linalg.norm(rp))
            along = (arm.a**2 - (arm.b**2 - dy**2) + d**2) / (2 * d)
            out = min(out, arm.a**2 - along**2, arm.b**2 - dy**2)
    return float(out)


def fixed_parts(loop: ArmLoop) -> tuple[list[RigidPart], list[RigidPart]]:
    """Point masses of both arms fixed in the rear frame (at S) and the front frame (at H)."""
    rear, front = [], []
    for side in (1.0, -1.0):
        mirror = np.array([1.0, side, 1.0])
        rear.append(point_mass(loop.upper[0], loop.shoulder * mirror))
        front.append(point_mass(loop.forearm[1], loop.grip * mirror))
    return rear, front


def symbol_values(loop: ArmLoop, bench: dict, moore: dict) -> dict[str, float]:
    """Values of :data:`symbolic.ARM_PARAMETERS` (Moore rear-frame coordinates from the rear hub,
    grip in front-frame coordinates from SymBRiM's steer hub, ``d1`` along the rear frame x)."""
    lam, r_r = bench["lam"], bench["rR"]

    def to_rear(p):
        dx, dz = p[0], p[2] + r_r
        return np.array([dx * np.cos(lam) - dz * np.sin(lam), p[1],
                         dx * np.sin(lam) + dz * np.cos(lam)])

    s = to_rear(loop.shoulder)
    h = to_rear(loop.grip) - np.array([moore["rear_frame_d1"], 0.0, 0.0])
    n = to_rear(loop.normal) - to_rear(np.zeros(3))
    mu1, mu2, mu3, cu = loop.upper
    mf1, mf2, mf3, cf = loop.forearm
    return {"arm_sx": s[0], "arm_sy": s[1], "arm_sz": s[2], "arm_hx": h[0], "arm_hy": h[1],
            "arm_hz": h[2], "arm_nx": n[0], "arm_ny": n[1], "arm_nz": n[2], "arm_a": loop.a,
            "arm_b": loop.b, "arm_cu": cu, "arm_cf": cf,
            "arm_sign": loop.sign, "arm_m_elbow": mu2 + mf1, "arm_m_upper": mu3,
            "arm_m_fore": mf3}


def nominal_posture(arms: YeadonArms | None = None) -> dict[str, float]:
    """The closed-form elbow at steer 0 and the original seat against Yeadon's elbow, m.

    ``elbow_distance_m``: with the tilted flexion axis (the model; zero to round-off);
    ``sagittal_gap_m``: how far the loop with the sagittal flexion axis is from closing
    (``d - a - b'``, positive: it cannot close); the elbow's and the grip's lateral offsets from
    the shoulder.
    """
    y = yeadon_arms() if arms is None else arms
    loop = arm_loop(y.shoulder, y)
    r = y.grip - y.shoulder
    b_proj = np.sqrt(loop.b**2 - r[1] ** 2)
    return {"elbow_distance_m": float(np.linalg.norm(loop.elbow() - y.elbow)),
            "sagittal_gap_m": float(np.hypot(r[0], r[2]) - loop.a - b_proj),
            "elbow_lateral_offset_m": float(y.elbow[1] - y.shoulder[1]),
            "grip_lateral_offset_m": float(r[1]),
            "flexion_axis_tilt_rad": float(np.arccos(loop.normal[1]))}
