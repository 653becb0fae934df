"""Conservation of angular momentum (CAM, Sec 3.1.2.3, Eq 3.19-3.25) and the momenta it
neglects (Sec 3.2.3.1, Eq 3.27-3.29).

CAM balances the generalised leg momentum ``L_L = -int f_L dt`` (Eq 3.28) with the generalised
momentum of the bicycle, ``M q' + L_L = const`` (Eq 3.20), i.e. Eq 3.8 without the speed and
gravity terms. With ``f_L = Re(sum_k coef_k (n_k w)^2 exp(i n_k w t))`` (Eq 3.14):

    L_L = Re(sum_k i n_k w coef_k exp(i n_k w t)),   q = Re(sum_k Q_k exp(i n_k w t)),
    Q_k = -M^-1 coef_k,

taking the constant so that the angles oscillate about zero. The CAM amplitudes depend only on
the mass matrix and the leg motion, not on speed or cadence (Sec 3.2.3).
"""

from __future__ import annotations

import numpy as np

from .momentum_terms import NEGLECTED_TERMS as NEGLECTED_TERMS  # Eq 3.29 (a leaf module)
from .params import LinearModel
from .response import Harmonics, harmonic_coefficients

__all__ = [
    "cam_coefficients", "cam_amplitude", "cam_time", "leg_momentum", "neglected_momenta_ratios",
]


def cam_coefficients(model: LinearModel, harmonics: Harmonics) -> np.ndarray:
    """Complex CAM response ``Q_k = -M^-1 coef_k`` per harmonic, shape (2, k) [roll; steer]."""
    _, coef = harmonic_coefficients(harmonics)
    return -np.linalg.solve(model.M, coef.T)


def cam_amplitude(model: LinearModel, harmonics: Harmonics) -> tuple[float, float]:
    """Roll and steer CAM amplitude at the cadence (the first harmonic) (rad)."""
    q = cam_coefficients(model, harmonics)
    return float(abs(q[0, 0])), float(abs(q[1, 0]))


def cam_time(model: LinearModel, harmonics: Harmonics, omega_rad_s: float,
             t_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CAM angles and angular rates in time (Fig 3.30).

    Returns
    -------
    angle_rad, rate_rad_s
        Shape (2, n_t): rows roll, steer.
    """
    n, _ = harmonic_coefficients(harmonics)
    q = cam_coefficients(model, harmonics)
    ph = np.exp(1j * np.multiply.outer(n * omega_rad_s, np.asarray(t_s, float)))  # (k, n_t)
    return np.real(q @ ph), np.real((q * (1j * n * omega_rad_s)) @ ph)


def leg_momentum(harmonics: Harmonics, omega_rad_s) -> np.ndarray:
    """Complex amplitude of the generalised leg momentum at the cadence (Eq 3.25, 3.28).

    ``L_L = i w coef_1`` (N m s), shape ``shape(omega) + (2,)``.
    """
    _, coef = harmonic_coefficients(harmonics)
    w = np.asarray(omega_rad_s, float)[..., None]
    return 1j * w * coef[0]


def neglected_momenta_ratios(model: LinearModel, harmonics: Harmonics, speed_m_s,
                             omega_rad_s) -> np.ndarray:
    """Neglected momenta of Eq 3.29 as ratios of the leg momentum, at the cadence harmonic.

    Each term is evaluated with the CAM solution ``q`` (as the thesis does, Sec 3.2.3.1):
    ``|v (C1 Q)_j| / |L_L,j|``, ``|g (K0 Q)_j / w| / |L_L,j|``, ``|v^2 (K2 Q)_j / w| / |L_L,j|``
    for ``j`` = roll, steer.

    Returns
    -------
    numpy.ndarray
        Shape ``broadcast(speed, omega) + (3, 2)``: term
        (:data:`pedalrepro.momentum_terms.NEGLECTED_TERMS`) x coordinate.
        Infinite at zero cadence.
    """
    q = cam_coefficients(model, harmonics)[:, 0]  # (2,)
    _, coef = harmonic_coefficients(harmonics)
    v, w = np.broadcast_arrays(np.asarray(speed_m_s, float), np.asarray(omega_rad_s, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        ll = np.abs(w)[..., None] * np.abs(coef[0])  # (..., 2)
        t1 = np.abs(v[..., None] * (model.C1 @ q)) / ll
        t2 = np.abs(model.g * (model.K0 @ q)) / (w[..., None] * ll)
        t3 = np.abs(v[..., None] ** 2 * (model.K2 @ q)) / (w[..., None] * ll)
    return np.stack([t1, t2, t3], axis=-2)
