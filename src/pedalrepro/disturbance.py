"""The pedalling disturbance: d'Alembert forces and torques, generalised roll and steer torques.

Thesis Sec 2.1.2 (Eq 2.8, 2.9), Sec 2.1.3 (virtual power, Eq 2.10-2.15), Sec 2.2.2
(Eq 2.18-2.24), Appendix B.2, and the harmonic forcing of the linear models (Eq 3.14).

Sign convention (checked against Eq 2.15, 2.22, 2.24 and Appendix B.2, and against the Table 4.1
model columns): the bicycle frame of Meijaard et al. (2007), ``x`` forward, ``y`` right, ``z``
down, origin at the crank axis A; roll ``phi`` positive to the right (about ``+x``), yaw ``psi``
positive to the right (about ``+z``), steer ``delta`` positive to the right (benchmark
convention). The right leg is at ``y = +l_hh / 2``. The d'Alembert torque of a point mass is
``-r x (m a)``; with ``a_y = 0`` its roll part is ``-y m a_z`` and its yaw part ``+y m a_x``, so
``T_phi = sum_odd m_L l_hh |Z_L| (n w)^2 cos(n w t + phi_Z)`` (Eq 2.22) and
``T_psi = -sum_odd m_L l_hh |X_L| (n w)^2 cos(n w t + phi_X)`` (Eq 2.23); the generalised steer
torque is ``T_delta = (c cos(lam) / w) T_psi`` (Eq 2.15 with the yaw-steer relation of Meijaard
2007, errata item 5).

Segment rotational inertia (Eq 2.9): every segment is a slender rod, ``I = m l^2 / 12`` about its
COM for pitch (``data/parameters/legs.yaml`` ``segment_inertia``). The segments only pitch, so
their inertia adds to the pitch torque only (Sec 2.1.2): roll, yaw and the generalised torques do
not depend on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import legs, params

__all__ = [
    "TorqueHarmonics", "steer_factor", "torque_harmonics", "LATERAL_MODELS",
    "segment_pitch_inertia_kg_m2", "dalembert_forces_n", "dalembert_torques_nm",
    "generalised_torques_nm", "nrmsd_percent", "PedallingDisturbance", "pedalling_disturbance",
    "section2_numbers", "to_arrays",
]


@dataclass(frozen=True)
class TorqueHarmonics:
    """Harmonic generalised pedalling torques (Eq 3.14).

    ``f(t) = Re( sum_k coef[k] * (n[k] * omega)**2 * exp(1j * n[k] * omega * t) )`` for
    ``coef`` = ``roll`` (roll torque) or ``steer`` (steer torque); units N m s^2 (multiply by
    ``(n omega)^2`` for N m). Roll and steer positive to the right (benchmark convention).

    Attributes
    ----------
    n
        Multiples of the cadence (int array).
    roll, steer
        Complex coefficients, ``m_L l_hh Z_L(n w)`` and ``-(c cos(lam) / w) m_L l_hh X_L(n w)``.
    bicycle, com
        What they were computed for.
    """

    n: np.ndarray
    roll: np.ndarray
    steer: np.ndarray
    bicycle: str = ""
    com: str = ""

    def evaluate(self, t_s: np.ndarray, cadence_rad_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Roll and steer torque (N m) at times ``t_s`` for cadence ``omega`` (Eq 3.14)."""
        t = np.asarray(t_s, dtype=float)
        wn = self.n * float(cadence_rad_s)
        phase = np.exp(1j * np.multiply.outer(t, wn)) * wn**2
        return np.real(phase @ self.roll), np.real(phase @ self.steer)


def steer_factor(bicycle: str) -> float:
    """Yaw-to-steer factor ``c cos(lam) / w`` of Eq 2.15 (``psi = factor * delta``)."""
    g = params.steer_geometry(bicycle)
    return g["c"] * np.cos(g["lam"]) / g["w"]


def torque_harmonics(bicycle: str, com: str = "O", harmonics=(1, 3, 5), *,
                     samples_per_revolution: int = 3600,
                     geometry: legs.LegGeometry | None = None,
                     steer_geometry: dict[str, float] | None = None) -> TorqueHarmonics:
    """Generalised pedalling roll and steer torque harmonics of Eq 3.14.

    ``f_L = sum_n m_L l_hh (n w)^2 [ |Z_L(n w)| cos(n w t + angle Z);
    -(c cos(lam) / w) |X_L(n w)| cos(n w t + angle X) ]`` with the right-leg COM Fourier
    coefficients of the dual four-bar (Table D.1, :func:`pedalrepro.legs.com_fourier`), ``m_L``
    and ``l_hh`` from ``legs.yaml`` and ``c``, ``w``, ``lam`` from
    :func:`pedalrepro.params.steer_geometry`.

    Parameters
    ----------
    bicycle
        ``"hybrid"``, ``"city"`` or ``"benchmark"``. The benchmark bicycle has no published rider
        geometry: it uses the hybrid leg geometry (Stratos seat, homogeneous segments by default)
        with the benchmark's own ``c``, ``w``, ``lam`` (Meijaard et al. 2007).
    com
        ``"O"`` (homogeneous segments, the thesis's choice) or ``"W"`` (Winter 1990).
    harmonics
        Multiples of the cadence; Eq 3.14 uses the odd ones (even multiples cancel between the
        legs, Sec 2.2.2), but any ``n >= 1`` is accepted (an even ``n`` gives the one-leg value).
    geometry
        Explicit leg geometry (any bicycle and rider, e.g. ``pedalrepro.own_bicycle``); replaces
        the ``legs.yaml`` geometry of ``bicycle`` (``com`` is then ignored).
    steer_geometry
        Explicit ``w``, ``c``, ``lam`` for the steer factor of Eq 2.15; replaces
        :func:`pedalrepro.params.steer_geometry` of ``bicycle``.

    Returns
    -------
    TorqueHarmonics
        Roll positive to the right, steer positive to the right (benchmark convention; see the
        module docstring for the derivation of the signs).

    Examples
    --------
    >>> h = torque_harmonics("hybrid")
    >>> roll, steer = h.evaluate([0.0, 0.25], 2 * np.pi)   # N m at 60 rpm
    """
    if geometry is None:
        geometry = legs.leg_geometry(bicycle, com)
    if steer_geometry is None:
        factor = steer_factor(bicycle)
    else:
        factor = steer_geometry["c"] * np.cos(steer_geometry["lam"]) / steer_geometry["w"]
    n = np.asarray(harmonics, dtype=int)
    x_l, z_l = legs.com_fourier(geometry, n, samples_per_revolution)
    scale = geometry.leg_mass_kg * geometry.hip_width_m
    return TorqueHarmonics(n=n, roll=scale * z_l, steer=-factor * scale * x_l,
                           bicycle=bicycle, com=com)


#: Lateral placement of the leg masses: ``"lumped"`` = the leg COM at ``y = +-l_hh / 2``
#: (Eq 2.21-2.24; reproduces the published NRMSDs, errata item 4); ``"segments"`` = each segment
#: at its own ``y`` of Eq B.18-B.23 (crank ``+-l_hh / 4``, shank and thigh ``+-l_hh / 2``).
LATERAL_MODELS: tuple[str, ...] = ("lumped", "segments")


def segment_pitch_inertia_kg_m2(geometry: legs.LegGeometry) -> dict[str, float]:
    """Pitch inertia of crank, shank and thigh about their COMs (``legs.yaml`` ``segment_inertia``).

    Only the slender-rod model ``I = m l^2 / 12`` is defined (see the module docstring).
    """
    model = params.legs().get("segment_inertia", {}).get("model", "slender_rod")
    if model != "slender_rod":
        raise ValueError(f"legs.yaml segment_inertia model {model!r} is not known: use slender_rod")
    m, length = legs.segment_masses_kg(geometry), legs.segment_lengths_m(geometry)
    return {s: m[s] * length[s] ** 2 / 12.0 for s in legs.SEGMENTS}


def _lateral_y_m(geometry: legs.LegGeometry, lateral: str) -> dict[str, float]:
    """Right-leg ``y`` of each segment COM (the left leg mirrors it)."""
    if lateral not in LATERAL_MODELS:
        raise ValueError(f"unknown lateral model {lateral!r}: expected one of {LATERAL_MODELS}")
    half = geometry.hip_width_m / 2.0
    if lateral == "lumped":
        return dict.fromkeys(legs.SEGMENTS, half)
    return {"crank": half / 2.0, "shank": half, "thigh": half}


def _point_mass_torque(mass_kg: float, y_m: float, pos_xz: np.ndarray,
                       acc_xz: np.ndarray) -> np.ndarray:
    """d'Alembert torque ``-r x (m a)`` of a point mass at ``(x, y, z)`` with ``a = (ax, 0, az)``.

    Returns ``(n_t, 3)``: roll (about x), pitch (about y), yaw (about z), about the crank axis A.
    """
    x, z = pos_xz[:, 0], pos_xz[:, 1]
    ax, az = acc_xz[:, 0], acc_xz[:, 1]
    return -mass_kg * np.stack([y_m * az, z * ax - x * az, -y_m * ax], axis=-1)


def dalembert_forces_n(right: legs.LegMotion, left: legs.LegMotion,
                       geometry: legs.LegGeometry) -> np.ndarray:
    """d'Alembert force of both legs, Eq 2.8: ``F = -m_L (a_riL + a_leL)``; ``(n_t, 3)``, z down."""
    m_l = geometry.leg_mass_kg
    f_xz = -m_l * (right.com_acc + left.com_acc)
    return np.stack([f_xz[:, 0], np.zeros(len(f_xz)), f_xz[:, 1]], axis=-1)


def dalembert_torques_nm(right: legs.LegMotion, left: legs.LegMotion,
                         geometry: legs.LegGeometry, *, lateral: str = "lumped",
                         inertia: bool = True) -> np.ndarray:
    """d'Alembert torques of both legs about the crank axis, Eq 2.9; ``(n_t, 3)`` roll/pitch/yaw.

    ``lateral="lumped"`` is Eq 2.9 as printed: each leg a point mass ``m_L`` at its COM, at
    ``y = +-l_hh / 2``, plus the segments' rotational inertia. ``lateral="segments"`` sums every
    segment as a rigid body at its own position (Eq B.18-B.23), the exact torque of the four-bar.
    ``inertia`` adds ``-I theta''`` of the six segments to the pitch torque (slender rods).
    """
    y = _lateral_y_m(geometry, lateral)
    torque = np.zeros((right.t_s.size, 3))
    for motion, side in ((right, 1.0), (left, -1.0)):
        if lateral == "lumped":
            torque += _point_mass_torque(geometry.leg_mass_kg, side * y["crank"], motion.com,
                                         motion.com_acc)
        else:
            masses = legs.segment_masses_kg(geometry)
            for s in legs.SEGMENTS:
                torque += _point_mass_torque(masses[s], side * y[s], motion.segment_com[s],
                                             motion.segment_com_acc[s])
        if inertia:
            inertias = segment_pitch_inertia_kg_m2(geometry)
            for s in legs.SEGMENTS:
                torque[:, 1] -= inertias[s] * motion.pitch_acc_rad_s2[s]
    return torque


def generalised_torques_nm(torque_nm: np.ndarray, bicycle: str) -> np.ndarray:
    """Generalised roll and steer torques from Cartesian ones, Eq 2.15; ``(n_t, 2)``.

    ``T_phi = T_x``, ``T_delta = (c cos(lam) / w) T_z`` (virtual power with ``theta-dot = 0`` and
    ``psi-dot = cos(lam) (v delta + c delta-dot) / w``, Eq 2.10-2.14).
    """
    return np.stack([torque_nm[:, 0], steer_factor(bicycle) * torque_nm[:, 2]], axis=-1)


def nrmsd_percent(reference: np.ndarray, approximation: np.ndarray) -> np.ndarray:
    """Normalised root-mean-square deviation of Eq 2.5 (per column), in percent.

    ``sqrt(mean((x - x_simple)^2)) / (max(x) - min(x)) * 100`` over one sampled period.
    """
    x = np.asarray(reference, dtype=float)
    s = np.asarray(approximation, dtype=float)
    rng = np.ptp(x, axis=0)
    if np.any(rng == 0):
        raise ValueError("NRMSD is undefined for a constant reference signal (zero range)")
    return np.sqrt(np.mean((x - s) ** 2, axis=0)) / rng * 100.0


@dataclass(frozen=True)
class PedallingDisturbance:
    """The pedalling disturbance over one revolution, four-bar vs cadence-only (Sec 2.2).

    Arrays are sampled at ``t_s``; ``crank_angle_rad = omega t``. ``force_n`` and ``torque_nm``
    are ``(n_t, 3)`` (x forward, y right, z down; roll, pitch, yaw), ``generalised_nm`` is
    ``(n_t, 2)`` (roll, steer). Suffix ``_simple``: the cadence-only skew-elliptical COM path of
    Eq 2.4 (first harmonic of the DFT), a point mass ``m_L`` per leg without segment rotation.
    """

    bicycle: str
    geometry: legs.LegGeometry
    cadence_rad_s: float
    t_s: np.ndarray
    crank_angle_rad: np.ndarray
    right: legs.LegMotion
    left: legs.LegMotion
    com_simple: np.ndarray
    com_simple_vel: np.ndarray
    com_simple_acc: np.ndarray
    force_n: np.ndarray
    torque_nm: np.ndarray
    generalised_nm: np.ndarray
    force_simple_n: np.ndarray
    torque_simple_nm: np.ndarray
    generalised_simple_nm: np.ndarray


def pedalling_disturbance(bicycle: str = "hybrid", com: str = "O",
                          cadence_rad_s: float = 2.0 * np.pi, *,
                          samples_per_revolution: int = 3600, lateral: str = "lumped",
                          inertia: bool = True,
                          geometry: legs.LegGeometry | None = None) -> PedallingDisturbance:
    """Leg kinematics, d'Alembert forces/torques and generalised torques over one revolution.

    Parameters
    ----------
    bicycle
        Sets the leg geometry (unless ``geometry`` is given) and the steer factor (Eq 2.15).
    com
        ``"O"`` or ``"W"`` segment COM fractions.
    cadence_rad_s
        ``omega`` (default 60 rpm, Sec 2.1.1).
    samples_per_revolution
        Samples of one revolution (even, so the left leg is an exact half-period shift).
    lateral, inertia
        See :func:`dalembert_torques_nm`.
    geometry
        Override of the leg geometry (e.g. another seat height).
    """
    if samples_per_revolution % 2:
        raise ValueError(f"samples_per_revolution must be even, got {samples_per_revolution}")
    geo = geometry if geometry is not None else legs.leg_geometry(bicycle, com)
    w = float(cadence_rad_s)
    right = legs.leg_motion(geo, w, samples_per_revolution=samples_per_revolution)
    left = legs.leg_motion(geo, w, samples_per_revolution=samples_per_revolution, left=True)
    force = dalembert_forces_n(right, left, geo)
    torque = dalembert_torques_nm(right, left, geo, lateral=lateral, inertia=inertia)

    # cadence-only motion, Eq 2.4: mean + first DFT harmonic; the left leg is pi out of phase
    mean = legs.fourier_mean(right.com)
    c1 = legs.fourier_coefficients(right.com, (1,))[0]
    phi = right.crank_angle_rad
    simple = [np.stack([legs.harmonic_signal(mean[k] if d == 0 else 0.0, [c1[k]], (1,), phi, d, w)
                        for k in range(2)], axis=-1) for d in range(3)]
    simple_left = [np.stack([legs.harmonic_signal(mean[k] if d == 0 else 0.0, [-c1[k]], (1,), phi,
                                                  d, w) for k in range(2)], axis=-1)
                   for d in range(3)]
    m_l = geo.leg_mass_kg
    f_xz = -m_l * (simple[2] + simple_left[2])
    force_simple = np.stack([f_xz[:, 0], np.zeros(len(f_xz)), f_xz[:, 1]], axis=-1)
    y = geo.hip_width_m / 2.0
    torque_simple = (_point_mass_torque(m_l, y, simple[0], simple[2])
                     + _point_mass_torque(m_l, -y, simple_left[0], simple_left[2]))
    return PedallingDisturbance(
        bicycle=bicycle, geometry=geo, cadence_rad_s=w, t_s=right.t_s, crank_angle_rad=phi,
        right=right, left=left, com_simple=simple[0], com_simple_vel=simple[1],
        com_simple_acc=simple[2], force_n=force, torque_nm=torque,
        generalised_nm=generalised_torques_nm(torque, bicycle), force_simple_n=force_simple,
        torque_simple_nm=torque_simple,
        generalised_simple_nm=generalised_torques_nm(torque_simple, bicycle))


def section2_numbers(bicycle: str = "hybrid", cadence_rad_s: float = 2.0 * np.pi,
                     samples_per_revolution: int = 3600,
                     lateral: str = "lumped") -> dict[str, float]:
    """The quantitative claims of Sec 2.2 computed by the model (names in SI/percent units).

    Returns
    -------
    dict
        ``nrmsd_com_x_percent``, ``nrmsd_com_z_percent`` (Eq 2.5, right-leg COM),
        ``nrmsd_roll_torque_percent``, ``nrmsd_steer_torque_percent`` (generalised torques),
        ``force_x_peak_n`` (largest ``|F_x|``), ``force_x_max_n``, ``force_x_min_n``,
        ``force_x_2w_amplitude_n``, ``force_z_peak_n``, ``force_z_2w_amplitude_n``,
        ``ow_change_x1_percent``, ``ow_change_z1_percent`` (first-harmonic COM amplitude, O vs W,
        relative to O), ``ow_change_higher_percent`` (harmonics n >= 2, mean over X and Z).
    """
    d = pedalling_disturbance(bicycle, "O", cadence_rad_s,
                              samples_per_revolution=samples_per_revolution, lateral=lateral)
    nr_com = nrmsd_percent(d.right.com, d.com_simple)
    nr_gen = nrmsd_percent(d.generalised_nm, d.generalised_simple_nm)
    f2 = np.abs(legs.fourier_coefficients(d.force_n[:, [0, 2]], (2,))[0])
    xo, zo = legs.com_fourier(legs.leg_geometry(bicycle, "O"), (1, 2, 3, 4, 5),
                              samples_per_revolution)
    xw, zw = legs.com_fourier(legs.leg_geometry(bicycle, "W"), (1, 2, 3, 4, 5),
                              samples_per_revolution)
    higher = np.concatenate([1 - np.abs(xw[1:]) / np.abs(xo[1:]),
                             1 - np.abs(zw[1:]) / np.abs(zo[1:])])
    return {
        "nrmsd_com_x_percent": float(nr_com[0]),
        "nrmsd_com_z_percent": float(nr_com[1]),
        "nrmsd_roll_torque_percent": float(nr_gen[0]),
        "nrmsd_steer_torque_percent": float(nr_gen[1]),
        "force_x_peak_n": float(np.max(np.abs(d.force_n[:, 0]))),
        "force_x_max_n": float(np.max(d.force_n[:, 0])),
        "force_x_min_n": float(np.min(d.force_n[:, 0])),
        "force_x_2w_amplitude_n": float(f2[0]),
        "force_z_peak_n": float(np.max(np.abs(d.force_n[:, 2]))),
        "force_z_2w_amplitude_n": float(f2[1]),
        "ow_change_x1_percent": float(100 * (1 - abs(xw[0]) / abs(xo[0]))),
        "ow_change_z1_percent": float(100 * (1 - abs(zw[0]) / abs(zo[0]))),
        "ow_change_higher_percent": float(100 * np.mean(higher)),
    }


def to_arrays(d: PedallingDisturbance, spectrum_harmonics: int = 20) -> dict[str, np.ndarray]:
    """Flatten a :class:`PedallingDisturbance` into named arrays (for an ``.npz`` file).

    Keys (right leg unless prefixed ``left_``; planar arrays ``(n_t, 2)`` = x, z with z down):
    ``t_s``, ``crank_angle_rad``, ``cadence_rad_s``, ``hip_width_m``, ``leg_mass_kg``,
    ``com_m``, ``com_vel_m_s``, ``com_acc_m_s2`` and their ``*_simple_*`` (cadence-only)
    counterparts, ``left_com_m``, ``left_com_simple_m``, ``pedal_m``, ``knee_m``, ``hip_m``,
    ``segment_com_<s>_m`` and ``left_segment_com_<s>_m`` (s = crank, shank, thigh),
    ``pitch_<s>_rad``, ``pitch_rate_<s>_rad_s``, ``pitch_acc_<s>_rad_s2``, ``force_n``,
    ``force_simple_n`` (n_t, 3), ``torque_nm``, ``torque_simple_nm`` (n_t, 3; roll, pitch, yaw),
    ``generalised_nm``, ``generalised_simple_nm`` (n_t, 2; roll, steer), and the COM position
    spectrum ``spectrum_n`` (0..spectrum_harmonics), ``spectrum_com_amplitude_m`` (n, 2).
    """
    r, le = d.right, d.left
    n = np.arange(spectrum_harmonics + 1)
    amp = np.abs(legs.fourier_coefficients(r.com, n[1:]))
    amp = np.vstack([np.abs(legs.fourier_mean(r.com))[None, :], amp])
    out: dict[str, np.ndarray] = {
        "t_s": d.t_s, "crank_angle_rad": d.crank_angle_rad,
        "cadence_rad_s": np.array(d.cadence_rad_s), "hip_width_m": np.array(d.geometry.hip_width_m),
        "leg_mass_kg": np.array(d.geometry.leg_mass_kg),
        "com_m": r.com, "com_vel_m_s": r.com_vel, "com_acc_m_s2": r.com_acc,
        "com_simple_m": d.com_simple, "com_simple_vel_m_s": d.com_simple_vel,
        "com_simple_acc_m_s2": d.com_simple_acc,
        "left_com_m": le.com, "left_com_simple_m": 2 * legs.fourier_mean(r.com) - d.com_simple,
        "pedal_m": r.pedal, "knee_m": r.knee, "hip_m": r.hip,
        "force_n": d.force_n, "force_simple_n": d.force_simple_n,
        "torque_nm": d.torque_nm, "torque_simple_nm": d.torque_simple_nm,
        "generalised_nm": d.generalised_nm, "generalised_simple_nm": d.generalised_simple_nm,
        "spectrum_n": n, "spectrum_com_amplitude_m": amp,
    }
    for s in legs.SEGMENTS:
        out[f"segment_com_{s}_m"] = r.segment_com[s]
        out[f"left_segment_com_{s}_m"] = le.segment_com[s]
        out[f"pitch_{s}_rad"] = r.pitch_rad[s]
        out[f"pitch_rate_{s}_rad_s"] = r.pitch_rate_rad_s[s]
        out[f"pitch_acc_{s}_rad_s2"] = r.pitch_acc_rad_s2[s]
    return out
