"""Leg kinematics: the dual four-bar mechanism of the pedalling legs (thesis Sec 2.1.1).

Each leg is a planar four-bar: the crank (cr), the lower leg (shank, ll), the upper leg (thigh,
ul) and the frame from the crank axis A to the hip (saddle) C as the base (Fig 2.1, Eq 2.1-2.2).
The crank turns isokinetically, ``theta_A = -omega t``, ``theta_A = 0`` with the right foot
forward; the left leg runs ``pi`` behind (``x_leL(t) = x_riL(t + pi / omega)``).

Conventions (they reproduce Table D.1 to 7 significant digits; ``book/deviations.md``,
"Conventions the thesis does not state"):

* crank axis A at the origin, ``x`` forward, ``z`` down (the bicycle frame of Meijaard et al.
  2007), ``y`` to the right; the right leg lies in the plane ``y = +l_hh / 2``;
* hip ``C = A + L (-cos(lambda_st), -sin(lambda_st))``, ``L`` = seat tube + seat post,
  ``lambda_st`` the seat-tube angle from the horizontal (hip behind and above A);
* pedal ``P = A + l_cr (cos(theta_A), -sin(theta_A))``;
* segment pitch angle ``theta``: a segment points along ``(cos(theta), -sin(theta))`` in
  ``(x, z)`` (positive pitch about ``+y``), so ``P + l_ll e(theta_ll) + l_ul e(theta_ul) = C``
  (Eq 2.1); the knee is the forward intersection of ``|K - P| = l_ll`` and ``|K - C| = l_ul``
  (knee not hyper-extended, Fig 2.1);
* segment COMs: crank at ``l_cr / 2`` from A; shank at ``f_ll l_ll`` from the pedal; thigh at
  ``f_ul l_ul`` from the knee (``O`` homogeneous: 0.5 / 0.5; ``W`` Winter 1990: 0.394 / 0.567);
* leg COM = mass-weighted mean of crank, shank and thigh (Eq 2.3 with its typo corrected,
  errata item 1).

Positions, velocities and accelerations are exact: the segment angular rates and accelerations
follow from differentiating the loop closure (Eq 2.1) analytically, so there is no finite
difference error. Fourier coefficients follow errata item 9:
``x(t) = X0 + sum_n |X(n)| cos(n omega t + phi_n)`` from the DFT of one revolution sampled
without a repeated end point.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from . import params

__all__ = [
    "BICYCLES", "COM_MODELS", "LegGeometry", "leg_geometry", "pedal_hip_distance_m",
    "unreachable_crank_angles_rad", "check_reach", "LegMotion", "SEGMENTS", "segment_masses_kg",
    "segment_lengths_m", "sample_times_s", "leg_motion", "fourier_coefficients", "fourier_mean",
    "com_fourier", "harmonic_signal",
]

#: The bicycles whose seat geometry is in ``legs.yaml``; ``benchmark`` borrows the hybrid legs.
BICYCLES: tuple[str, ...] = ("hybrid", "city", "benchmark")
#: COM-fraction sets of ``legs.yaml`` ``com_fractions``.
COM_MODELS: tuple[str, ...] = ("O", "W")


@dataclass(frozen=True)
class LegGeometry:
    """Geometry and mass distribution of one leg + crank four-bar (Sec 2.1.1, Table D.1 caption).

    Attributes
    ----------
    name
        A label naming the geometry in messages (e.g. ``"city (O), L = 0.77 m"``).
    seat_tube_angle_rad
        Seat-tube angle from the horizontal (errata item 8).
    seat_tube_plus_post_m
        Distance ``L`` from the crank axis A to the hip C along the seat tube.
    crank_length_m, shank_length_m, thigh_length_m
        ``l_cr``, ``l_ll``, ``l_ul``.
    crank_mass_kg, shank_mass_kg, thigh_mass_kg
        ``m_cr``, ``m_ll``, ``m_ul`` (one leg).
    hip_width_m
        ``l_hh``, hip joint to hip joint.
    shank_com_from_pedal, thigh_com_from_knee
        Segment COM fractions (``O`` or ``W``).
    crank_com_fraction
        Crank COM as a fraction of ``l_cr`` from the crank axis (0.5, Eq B.18).
    """

    name: str
    seat_tube_angle_rad: float
    seat_tube_plus_post_m: float
    crank_length_m: float
    shank_length_m: float
    thigh_length_m: float
    crank_mass_kg: float
    shank_mass_kg: float
    thigh_mass_kg: float
    hip_width_m: float
    shank_com_from_pedal: float
    thigh_com_from_knee: float
    crank_com_fraction: float = 0.5

    @property
    def leg_mass_kg(self) -> float:
        """``m_L = m_cr + m_ll + m_ul``: the mass of one leg including its crank."""
        return self.crank_mass_kg + self.shank_mass_kg + self.thigh_mass_kg

    @property
    def hip_xz_m(self) -> np.ndarray:
        """Hip C relative to the crank axis A, ``(x, z)`` in m (z down)."""
        lam = self.seat_tube_angle_rad
        return self.seat_tube_plus_post_m * np.array([-np.cos(lam), -np.sin(lam)])

    def with_seat(self, seat_tube_plus_post_m: float) -> LegGeometry:
        """The same leg with another seat-tube + seat-post length (name updated)."""
        base = self.name.split(", L =")[0]
        return replace(self, seat_tube_plus_post_m=float(seat_tube_plus_post_m),
                       name=f"{base}, L = {seat_tube_plus_post_m:g} m")


def leg_geometry(bicycle: str = "hybrid", com: str = "O", *,
                 seat_tube_plus_post_m: float | None = None) -> LegGeometry:
    """The leg geometry of a thesis bicycle from ``data/parameters/legs.yaml``.

    Parameters
    ----------
    bicycle
        ``"hybrid"`` (Batavus Stratos), ``"city"`` (Batavus Browser, seat post shortened to
        0.19 m as in Sec 2.1.1) or ``"benchmark"`` (no rider geometry is published for the
        Meijaard benchmark bicycle: the hybrid legs are used).
    com
        ``"O"`` homogeneous segments (Moore et al. 2009) or ``"W"`` Winter (1990) COM fractions.
    seat_tube_plus_post_m
        Override of ``L`` (e.g. the city bicycle's original 0.77 m).
    """
    if bicycle not in BICYCLES:
        raise ValueError(f"unknown bicycle {bicycle!r}: expected one of {BICYCLES}")
    if com not in COM_MODELS:
        raise ValueError(f"unknown COM model {com!r}: expected one of {COM_MODELS}")
    p = params.legs()
    seat = p["seat_geometry"]["hybrid" if bicycle == "benchmark" else bicycle]
    frac = p["com_fractions"][com]
    length = float(seat["seat_tube_plus_post_m"] if seat_tube_plus_post_m is None
                   else seat_tube_plus_post_m)
    return LegGeometry(
        name=f"{bicycle} ({com}), L = {length:g} m",
        seat_tube_angle_rad=float(np.deg2rad(seat["seat_tube_angle_deg"])),
        seat_tube_plus_post_m=length,
        crank_length_m=float(p["crank_length_m"]),
        shank_length_m=float(p["shank_length_m"]),
        thigh_length_m=float(p["thigh_length_m"]),
        crank_mass_kg=float(p["crank_mass_kg"]),
        shank_mass_kg=float(p["shank_mass_kg"]),
        thigh_mass_kg=float(p["thigh_mass_kg"]),
        hip_width_m=float(p["hip_width_m"]),
        shank_com_from_pedal=float(frac["shank_from_pedal"]),
        thigh_com_from_knee=float(frac["thigh_from_knee"]),
    )


def _e(theta: np.ndarray) -> np.ndarray:
    """Unit vector of a segment with pitch angle ``theta``: ``(cos, -sin)``, shape (..., 2)."""
    return np.stack([np.cos(theta), -np.sin(theta)], axis=-1)


def _e_prime(theta: np.ndarray) -> np.ndarray:
    """``d e / d theta = (-sin, -cos)``."""
    return np.stack([-np.sin(theta), -np.cos(theta)], axis=-1)


def pedal_hip_distance_m(geometry: LegGeometry, crank_angle_rad: np.ndarray) -> np.ndarray:
    """Distance pedal-hip ``|C - P|`` at crank angles ``omega t`` (``theta_A = -omega t``)."""
    theta_a = -np.asarray(crank_angle_rad, dtype=float)
    pedal = geometry.crank_length_m * _e(theta_a)
    return np.linalg.norm(geometry.hip_xz_m - pedal, axis=-1)


def unreachable_crank_angles_rad(geometry: LegGeometry, samples: int = 36000) -> np.ndarray:
    """Crank angles ``omega t`` in ``[0, 2 pi)`` at which the leg cannot close the four-bar."""
    angle = 2.0 * np.pi * np.arange(samples) / samples
    d = pedal_hip_distance_m(geometry, angle)
    too_far = d > geometry.shank_length_m + geometry.thigh_length_m
    too_near = d < abs(geometry.thigh_length_m - geometry.shank_length_m)
    return angle[too_far | too_near]


def check_reach(geometry: LegGeometry) -> None:
    """Raise ``ValueError`` naming the geometry when the leg cannot reach the pedal all round.

    The four-bar closes iff ``|l_ul - l_ll| <= |C - P| <= l_ul + l_ll`` at every crank angle; the
    extremes of ``|C - P|`` are ``L +- l_cr`` (pedal pointing away from or towards the hip), so
    the check is exact. The message gives the crank-angle range (``omega t``, right foot forward
    at 0) where the leg is too short, e.g. the city bicycle's original 0.77 m seat (Sec 2.1.1,
    Sec 3.1.1.3, errata item 14).
    """
    big = geometry.seat_tube_plus_post_m + geometry.crank_length_m
    small = abs(geometry.seat_tube_plus_post_m - geometry.crank_length_m)
    reach = geometry.shank_length_m + geometry.thigh_length_m
    fold = abs(geometry.thigh_length_m - geometry.shank_length_m)
    if big <= reach and small >= fold:
        return
    bad = np.rad2deg(unreachable_crank_angles_rad(geometry))
    where = f"crank angles {bad.min():.1f}-{bad.max():.1f} deg" if bad.size else "some crank angles"
    if big > reach:
        why = (f"the leg is {1e3 * (big - reach):.1f} mm short: hip-to-pedal distance up to "
               f"{big:.3f} m > l_ll + l_ul = {reach:.3f} m")
    else:
        why = f"hip-to-pedal distance down to {small:.3f} m < |l_ul - l_ll| = {fold:.3f} m"
    raise ValueError(
        f"leg geometry '{geometry.name}' cannot reach the pedal over a full crank revolution: "
        f"{why}, at {where} (omega t, right foot forward at 0)")


@dataclass(frozen=True)
class LegMotion:
    """Kinematics of one leg over the sampled times (Sec 2.1.1, Appendix B.1, Fig D.1).

    All planar vectors have shape ``(n_t, 2)`` with columns ``(x, z)`` (m, z down), relative to
    the crank axis A; angles are segment pitch angles (rad).
    """

    t_s: np.ndarray
    crank_angle_rad: np.ndarray  #: ``omega t`` (= ``-theta_A``)
    pedal: np.ndarray
    knee: np.ndarray
    hip: np.ndarray
    #: pitch angle, rate, acceleration of crank, shank, thigh: dict name -> (n_t,) arrays
    pitch_rad: dict[str, np.ndarray]
    pitch_rate_rad_s: dict[str, np.ndarray]
    pitch_acc_rad_s2: dict[str, np.ndarray]
    #: segment COMs: dict name -> (n_t, 2) position, velocity, acceleration
    segment_com: dict[str, np.ndarray]
    segment_com_vel: dict[str, np.ndarray]
    segment_com_acc: dict[str, np.ndarray]
    #: leg COM (mass-weighted mean, Eq 2.3 corrected)
    com: np.ndarray
    com_vel: np.ndarray
    com_acc: np.ndarray


SEGMENTS: tuple[str, ...] = ("crank", "shank", "thigh")


def segment_masses_kg(geometry: LegGeometry) -> dict[str, float]:
    """Masses of crank, shank and thigh of one leg."""
    return {"crank": geometry.crank_mass_kg, "shank": geometry.shank_mass_kg,
            "thigh": geometry.thigh_mass_kg}


def segment_lengths_m(geometry: LegGeometry) -> dict[str, float]:
    """Lengths of crank, shank and thigh."""
    return {"crank": geometry.crank_length_m, "shank": geometry.shank_length_m,
            "thigh": geometry.thigh_length_m}


def sample_times_s(cadence_rad_s: float, samples_per_revolution: int) -> np.ndarray:
    """One revolution ``t = k T / N``, ``k = 0..N-1`` (no repeated end point, errata item 9)."""
    if cadence_rad_s <= 0:
        raise ValueError(f"cadence must be positive, got {cadence_rad_s} rad/s")
    if samples_per_revolution < 8:
        raise ValueError(f"need at least 8 samples per revolution, got {samples_per_revolution}")
    period = 2.0 * np.pi / cadence_rad_s
    return period * np.arange(samples_per_revolution) / samples_per_revolution


def leg_motion(geometry: LegGeometry, cadence_rad_s: float, t_s: np.ndarray | None = None, *,
               samples_per_revolution: int = 3600, left: bool = False) -> LegMotion:
    """Exact kinematics of the right (or left) leg four-bar at a constant cadence.

    Parameters
    ----------
    geometry
        The leg (see :func:`leg_geometry`); checked with :func:`check_reach` first.
    cadence_rad_s
        ``omega = -theta_A-dot`` (rad/s).
    t_s
        Times (s); default one revolution of ``samples_per_revolution`` samples.
    left
        The left leg: crank angle shifted by ``pi`` (Eq 2.2).

    Returns
    -------
    LegMotion
        Angles, rates and accelerations from the differentiated loop closure (Eq 2.1):
        ``P' + l_ll th_ll' e'(th_ll) + l_ul th_ul' e'(th_ul) = 0`` and its time derivative.
    """
    check_reach(geometry)
    omega = float(cadence_rad_s)
    t = sample_times_s(omega, samples_per_revolution) if t_s is None else np.asarray(t_s, float)
    phi = omega * t + (np.pi if left else 0.0)  # crank angle omega t (+ pi for the left leg)
    l_cr, l_ll, l_ul = geometry.crank_length_m, geometry.shank_length_m, geometry.thigh_length_m
    hip = np.broadcast_to(geometry.hip_xz_m, (t.size, 2)).copy()

    th_a = -phi
    pedal = l_cr * _e(th_a)
    pedal_vel = l_cr * _e_prime(th_a) * (-omega)
    pedal_acc = -l_cr * _e(th_a) * omega**2

    # knee: forward intersection of the circles around P (l_ll) and C (l_ul)
    d_vec = hip - pedal
    d = np.linalg.norm(d_vec, axis=-1)
    u = d_vec / d[:, None]
    a = (l_ll**2 - l_ul**2 + d**2) / (2.0 * d)
    h = np.sqrt(np.clip(l_ll**2 - a**2, 0.0, None))
    n_fwd = np.stack([-u[:, 1], u[:, 0]], axis=-1)  # x > 0 because the hip is above the pedal
    knee = pedal + a[:, None] * u + h[:, None] * n_fwd

    sk, th = knee - pedal, hip - knee
    th_ll = np.arctan2(-sk[:, 1], sk[:, 0])
    th_ul = np.arctan2(-th[:, 1], th[:, 0])

    # rates: l_ll e'(th_ll) w_ll + l_ul e'(th_ul) w_ul = -P'
    jac = np.stack([l_ll * _e_prime(th_ll), l_ul * _e_prime(th_ul)], axis=-1)  # (n, 2, 2)
    rates = np.linalg.solve(jac, -pedal_vel[..., None])[..., 0]
    w_ll, w_ul = rates[:, 0], rates[:, 1]
    # accelerations: J [al_ll, al_ul] = -P'' + l_ll w_ll^2 e(th_ll) + l_ul w_ul^2 e(th_ul)
    rhs = -pedal_acc + l_ll * w_ll[:, None] ** 2 * _e(th_ll) + l_ul * w_ul[:, None] ** 2 * _e(th_ul)
    accs = np.linalg.solve(jac, rhs[..., None])[..., 0]
    al_ll, al_ul = accs[:, 0], accs[:, 1]

    knee_vel = pedal_vel + l_ll * w_ll[:, None] * _e_prime(th_ll)
    knee_acc = (pedal_acc + l_ll * al_ll[:, None] * _e_prime(th_ll)
                - l_ll * w_ll[:, None] ** 2 * _e(th_ll))

    def along(base, base_v, base_a, length, theta, rate, acc):
        pos = base + length * _e(theta)
        vel = base_v + length * rate[:, None] * _e_prime(theta)
        accel = (base_a + length * acc[:, None] * _e_prime(theta)
                 - length * rate[:, None] ** 2 * _e(theta))
        return pos, vel, accel

    zero = np.zeros_like(t)
    f_cr = geometry.crank_com_fraction
    c_cr = along(np.zeros_like(pedal), np.zeros_like(pedal), np.zeros_like(pedal), f_cr * l_cr,
                 th_a, np.full_like(t, -omega), zero)
    c_ll = along(pedal, pedal_vel, pedal_acc, geometry.shank_com_from_pedal * l_ll,
                 th_ll, w_ll, al_ll)
    c_ul = along(knee, knee_vel, knee_acc, geometry.thigh_com_from_knee * l_ul, th_ul, w_ul, al_ul)

    masses = segment_masses_kg(geometry)
    m_l = geometry.leg_mass_kg
    seg = {"crank": c_cr, "shank": c_ll, "thigh": c_ul}
    com = [sum(masses[s] * seg[s][k] for s in SEGMENTS) / m_l for k in range(3)]
    return LegMotion(
        t_s=t, crank_angle_rad=phi, pedal=pedal, knee=knee, hip=hip,
        pitch_rad={"crank": th_a, "shank": th_ll, "thigh": th_ul},
        pitch_rate_rad_s={"crank": np.full_like(t, -omega), "shank": w_ll, "thigh": w_ul},
        pitch_acc_rad_s2={"crank": zero, "shank": al_ll, "thigh": al_ul},
        segment_com={s: seg[s][0] for s in SEGMENTS},
        segment_com_vel={s: seg[s][1] for s in SEGMENTS},
        segment_com_acc={s: seg[s][2] for s in SEGMENTS},
        com=com[0], com_vel=com[1], com_acc=com[2],
    )


def fourier_coefficients(signal: np.ndarray, harmonics: np.ndarray | tuple[int, ...]) -> np.ndarray:
    """Complex Fourier coefficients ``|X(n)| exp(i phi_n)`` of one sampled period (errata 9).

    ``signal`` holds one period along axis 0 (no repeated end point); the result satisfies
    ``x(t) = X0 + sum_n |X(n)| cos(n omega t + phi_n)``, i.e. ``|X(n)| = 2 |DFT(n)| / N`` and
    ``phi_n = angle(DFT(n))`` (Sec 3.1.2.1.1). ``harmonics`` are integers ``>= 1``; the mean is
    ``fourier_mean``.
    """
    x = np.asarray(signal, dtype=float)
    n = np.asarray(harmonics, dtype=int)
    if np.any(n < 1) or np.any(n >= x.shape[0] // 2):
        raise ValueError(f"harmonics must lie in 1..{x.shape[0] // 2 - 1}, got {n.tolist()}")
    spec = np.fft.rfft(x, axis=0)
    return 2.0 * spec[n] / x.shape[0]


def fourier_mean(signal: np.ndarray) -> np.ndarray:
    """``X(0)``: the mean over one sampled period."""
    return np.mean(np.asarray(signal, dtype=float), axis=0)


def com_fourier(geometry: LegGeometry, harmonics: tuple[int, ...] | np.ndarray = (1, 2, 3, 4, 5),
                samples_per_revolution: int = 3600) -> tuple[np.ndarray, np.ndarray]:
    """Right-leg COM Fourier coefficients ``X_L(n omega)``, ``Z_L(n omega)`` (Table D.1).

    They do not depend on the cadence (the path is geometric; time only scales), so the DFT is
    taken over one revolution at 1 rad/s. Returns two complex arrays
    ``|X(n)| exp(i phi_X(n))`` and ``|Z(n)| exp(i phi_Z(n))`` (m).
    """
    n = tuple(int(k) for k in np.atleast_1d(harmonics))
    coef = _com_fourier_cached(geometry, n, int(samples_per_revolution))
    return coef[:, 0].copy(), coef[:, 1].copy()


@lru_cache(maxsize=64)
def _com_fourier_cached(geometry: LegGeometry, harmonics: tuple[int, ...],
                        samples_per_revolution: int) -> np.ndarray:
    """Cached core of :func:`com_fourier` (the geometry is a frozen, hashable dataclass)."""
    motion = leg_motion(geometry, 1.0, samples_per_revolution=samples_per_revolution)
    coef = fourier_coefficients(motion.com, harmonics)
    coef.flags.writeable = False
    return coef


def harmonic_signal(mean: float, coefficients: np.ndarray, harmonics: np.ndarray | tuple[int, ...],
                    omega_t_rad: np.ndarray, derivative: int = 0,
                    cadence_rad_s: float = 1.0) -> np.ndarray:
    """Evaluate ``X0 + sum Re(C_n exp(i n omega t))`` or its ``derivative``-th time derivative.

    Used for the cadence-only (skew-elliptical) motion of Eq 2.4 (``harmonics = (1,)``).
    """
    n = np.asarray(harmonics, dtype=float)
    c = np.asarray(coefficients, dtype=complex)
    phase = np.exp(1j * np.outer(np.asarray(omega_t_rad, dtype=float), n))
    factor = (1j * n * cadence_rad_s) ** derivative
    out = np.real(phase @ (c * factor))
    return out + (mean if derivative == 0 else 0.0)
