"""The published gain rules of the rider-control model (HumanControl ``generate_data.m``).

Successive loop closure, inner loop first (Hess, Moore & Hubbard 2012; Moore 2012,
dissertation, chapter "Control"; the rules of the repository's current ``generate_data.m``,
functions ``compute_inner_gains`` and ``find_open_gain``):

- ``kDelta``: with only the steer-angle loop closed, one complex pole pair of the closed loop
  (the neuromuscular pair) has damping ratio 0.1289;
- ``kPhiDot``: with the roll-rate loop closed too, a complex pair has damping ratio 0.0855
  (``compute_inner_gains`` factors the closed-loop characteristic polynomial as
  ``(s^2 + 2 zeta w s + w^2) x quartic``; here the same condition is solved by following
  that pair's eigenvalue while a secant iteration moves the gain);
- ``kPhi``, ``kPsi``, ``kY``: the open-loop transfer function of the roll, heading and
  lateral-position loops (inner loops closed, unit gain) has magnitude one at 2, 1 and
  0.5 rad/s: ``k = 1 / |L(j w_c)|``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .plant import GAIN_NAMES, Plant, closed_matrix, open_loop_response

__all__ = [
    "ZETA_DELTA", "ZETA_PHIDOT", "CROSSOVER_RAD_S", "INNER_GUESS", "RuleSettings", "DEFAULT_RULES",
    "GainResult", "rule_gains", "rule_gains_sweep",
]

#: Damping ratios of the closed-loop neuromuscular pair (``generate_data.m``).
ZETA_DELTA = 0.1289
ZETA_PHIDOT = 0.0855
#: Open-loop crossover frequencies of the roll, heading and lateral loops (rad/s).
CROSSOVER_RAD_S: tuple[float, float, float] = (2.0, 1.0, 0.5)
#: Starting guess of the inner-gain solve (kDelta, omega_delta, kPhiDot, omega_phidot): the
#: gains of ``compute_inner_gains``'s own guess (the benchmark at 5 m/s); the pairs' natural
#: frequencies 14 rad/s (where the damped pairs of that solution lie).
INNER_GUESS: tuple[float, float, float, float] = (46.5520391, 14.0, -0.0521602768, 14.0)


@dataclass(frozen=True)
class RuleSettings:
    """Targets of the gain rules (defaults: ``generate_data.m``, steer-torque input)."""

    zeta_delta: float = ZETA_DELTA
    zeta_phidot: float = ZETA_PHIDOT
    crossover_rad_s: tuple[float, float, float] = CROSSOVER_RAD_S


def _damping(lam: complex) -> float:
    return float(-lam.real / abs(lam))


def _damped_pair_gain(p: Plant, gains: np.ndarray, loop: int, zeta: float,
                      guess: tuple[float, float], tol: float = 1e-12,
                      max_iter: int = 100) -> tuple[float, float]:
    """Gain of ``loop`` (0 or 1) giving the tracked closed-loop pair damping ``zeta``.

    The pair is the complex eigenvalue (upper half plane) of the closed loop at the guessed
    gain nearest ``w_guess (-zeta + i sqrt(1 - zeta^2))``; it is followed by continuity
    (nearest eigenvalue) while a secant iteration on the gain drives its damping ratio to
    ``zeta``. Returns the gain and the pair's natural frequency (rad/s).
    """
    def pair(k: float, near: complex) -> complex:
        g = np.array(gains, float)
        g[loop] = k
        lam = np.linalg.eigvals(closed_matrix(p, g, loop + 1))
        lam = lam[lam.imag > 0]
        if lam.size == 0:
            raise RuntimeError(f"gain rule for loop {loop}: no complex closed-loop pole at "
                               f"gain {k} (v={p.speed_m_s} m/s)")
        return complex(lam[np.argmin(np.abs(lam - near))])

    k0, w0 = float(guess[0]), float(guess[1])
    lam0 = pair(k0, w0 * complex(-zeta, np.sqrt(1.0 - zeta**2)))
    f0 = _damping(lam0) - zeta
    k1 = k0 * (1.0 + 1e-3)
    lam1 = pair(k1, lam0)
    f1 = _damping(lam1) - zeta
    for _ in range(max_iter):
        if abs(f1) < tol:
            return k1, abs(lam1)
        if f1 == f0:
            break
        k2 = k1 - f1 * (k1 - k0) / (f1 - f0)
        k0, f0, lam0 = k1, f1, lam1
        # limit the step so the tracked pair stays the same one
        k1 = k0 + float(np.clip(k2 - k0, -0.5 * abs(k0) - 1e-9, 0.5 * abs(k0) + 1e-9))
        lam1 = pair(k1, lam0)
        f1 = _damping(lam1) - zeta
    raise RuntimeError(f"gain rule for loop {loop} (damping {zeta}) did not converge at "
                       f"v={p.speed_m_s} m/s (last gain {k1}, damping error {f1:.2e})")


#: The rules of ``generate_data.m`` (steer-torque input).
DEFAULT_RULES = RuleSettings()


@dataclass(frozen=True)
class GainResult:
    """Gains (``kDelta, kPhiDot, kPhi, kPsi, kY``) and the frequencies of the damped pairs."""

    gains: np.ndarray
    omega_delta_rad_s: float
    omega_phidot_rad_s: float

    def as_dict(self) -> dict[str, float]:
        """Gains by name."""
        return dict(zip(GAIN_NAMES, map(float, self.gains), strict=True))


def rule_gains(p: Plant, settings: RuleSettings = DEFAULT_RULES,
               guess: tuple[float, float, float, float] = INNER_GUESS) -> GainResult:
    """The five gains by the published rules (module docstring) for one plant (one speed).

    Parameters
    ----------
    p
        The plant (:func:`pedalrepro.rider.plant.plant`).
    settings
        Damping ratios and crossover frequencies.
    guess
        Starting point ``(kDelta, w_delta, kPhiDot, w_phidot)`` of the inner solve; sweeps pass
        the previous speed's solution (continuation).
    """
    g = np.zeros(5)
    g[0], w_d = _damped_pair_gain(p, g, 0, settings.zeta_delta, (guess[0], guess[1]))
    g[1], w_p = _damped_pair_gain(p, g, 1, settings.zeta_phidot, (guess[2], guess[3]))
    for loop, wc in zip((2, 3, 4), settings.crossover_rad_s, strict=True):
        g[loop] = 1.0 / abs(open_loop_response(p, g, loop, np.array([wc]))[0])
    return GainResult(g, w_d, w_p)


def rule_gains_sweep(plants: list[Plant], settings: RuleSettings = DEFAULT_RULES,
                     guess: tuple[float, float, float, float] = INNER_GUESS
                     ) -> list[GainResult]:
    """:func:`rule_gains` over plants in speed order, each started from the previous result."""
    out = []
    for p in plants:
        res = rule_gains(p, settings, guess)
        out.append(res)
        guess = (res.gains[0], res.omega_delta_rad_s, res.gains[1], res.omega_phidot_rad_s)
    return out
