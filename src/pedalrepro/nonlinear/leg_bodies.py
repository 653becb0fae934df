"""The legs and cranks of the non-linear models as rigid bodies over one crank revolution.

The four-bar leg motion of :mod:`pedalrepro.legs` (thesis Sec 2.1.1) gives each crank, shank and
thigh (:data:`pedalrepro.nonlinear.symbolic.LEG_BODIES`) a path; here those paths become the
prescribed coordinates of method NP (SymBRiM's rear-frame coordinates) and the rigid parts that
the models lump into body B (revolution averaged, or frozen at crank angle 0 for NT,
Sec 3.1.1.3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import legs
from . import symbolic
from .rigid import RigidPart

__all__ = ["LegRevolution", "leg_revolution"]


@dataclass(frozen=True)
class LegRevolution:
    """One crank revolution of the leg bodies.

    Attributes
    ----------
    parameters
        ``<body>_y`` (m), ``<body>_m`` (kg), ``<body>_I`` (kg m^2) of each leg body.
    signals
        Rear-frame x, z and pitch of each body (rows, 3 per body in ``LEG_BODIES`` order) at
        ``samples`` instants of the revolution.
    mean_parts
        Revolution-averaged part of each body (benchmark frame): COM path spread included.
    frozen_parts
        Each body at ``t = 0`` (crank horizontal, right foot forward).
    """

    parameters: dict[str, float]
    signals: np.ndarray
    mean_parts: list[RigidPart]
    frozen_parts: list[RigidPart]


def leg_revolution(geom: legs.LegGeometry, crank_axis_m: np.ndarray, lam_rad: float,
                   rear_radius_m: float, omega_rad_s: float, samples: int) -> LegRevolution:
    """The leg bodies over one revolution at cadence ``omega_rad_s``.

    Parameters
    ----------
    geom
        Leg geometry of the bicycle (:func:`pedalrepro.legs.leg_geometry`).
    crank_axis_m
        Crank axis A in the benchmark frame (x forward, z down, rear contact origin), m.
    lam_rad, rear_radius_m
        Steer-axis tilt and rear wheel radius (benchmark ``lam``, ``rR``): the rear frame of
        SymBRiM is pitched by ``lam`` about the rear wheel centre.
    omega_rad_s, samples
        Cadence and samples per revolution.
    """
    a_pt = np.asarray(crank_axis_m, float)
    lam, r_r, omega = lam_rad, rear_radius_m, omega_rad_s
    half = geom.hip_width_m / 2.0
    lateral = {"crank": half / 2.0, "shank": half, "thigh": half}
    masses = legs.segment_masses_kg(geom)
    lengths = legs.segment_lengths_m(geom)
    t = 2 * np.pi / omega * np.arange(samples) / samples
    leg_params: dict[str, float] = {}
    rows = []  # per body: x_frame, z_frame, th_frame over one revolution
    mean_parts, frozen_parts = [], []
    for name in symbolic.LEG_BODIES:
        seg, side = name.split("_")
        motion = legs.leg_motion(geom, omega, t, left=side == "l")
        xz = motion.segment_com[seg] + a_pt[[0, 2]]
        th = motion.pitch_rad[seg]
        # benchmark (x, z) -> rear frame (Moore): rotate by lam about y, origin rear wheel centre
        dx, dz = xz[:, 0], xz[:, 1] + r_r
        xf = dx * np.cos(lam) - dz * np.sin(lam)
        zf = dx * np.sin(lam) + dz * np.cos(lam)
        rows += [xf, zf, np.unwrap(th - lam)]
        y = lateral[seg] * (1 if side == "r" else -1)
        m = masses[seg]
        i_perp = m * lengths[seg] ** 2 / 12.0
        leg_params.update({f"{name}_y": y, f"{name}_m": m, f"{name}_I": i_perp})
        # revolution average in the benchmark frame
        com = np.array([xz[:, 0].mean(), y, xz[:, 1].mean()])
        c2, s2 = np.mean(np.cos(th) ** 2), np.mean(np.sin(th) ** 2)
        cs = np.mean(np.cos(th) * -np.sin(th))
        # rod along e = (cos th, 0, -sin th): I = i_perp (1 - e e^T)
        eet = np.array([[c2, 0, cs], [0, 0, 0], [cs, 0, s2]])
        i_c = i_perp * (np.eye(3) - eet)
        spread = np.zeros((3, 3))
        for k, j in ((0, 0), (2, 2), (0, 2)):
            a_, b_ = (xz[:, 0] if k == 0 else xz[:, 1]), (xz[:, 0] if j == 0 else xz[:, 1])
            spread[k, j] = np.mean((a_ - a_.mean()) * (b_ - b_.mean()))
        spread[2, 0] = spread[0, 2]
        # spread of the COM path adds m (|r|^2 I - r r^T) averaged
        i_c = i_c + m * (np.trace(spread) * np.eye(3) - spread)
        mean_parts.append(RigidPart(m, com, i_c))
        e0 = np.array([np.cos(th[0]), 0.0, -np.sin(th[0])])
        frozen_parts.append(RigidPart(m, np.array([xz[0, 0], y, xz[0, 1]]),
                                      i_perp * (np.eye(3) - np.outer(e0, e0))))
    return LegRevolution(leg_params, np.array(rows), mean_parts, frozen_parts)
