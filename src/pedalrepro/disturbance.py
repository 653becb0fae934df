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
                     samples_per_revolution: int = 3600) -> TorqueHarmonics:
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
    geometry = legs.leg_geometry(bicycle, com)
    n = np.asarray(harmonics, dtype=int)
    x_l, z_l = legs.com_fourier(geometry, n, samples_per_revolution)
    scale = geometry.leg_mass_kg * geometry.hip_width_m
    return TorqueHarmonics(n=n, roll=scale * z_l, steer=-steer_factor(bicycle) * scale * x_l,
                           bicycle=bicycle, com=com)
