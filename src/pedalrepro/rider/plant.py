"""The plant of the rider-control model: Eq 3.1 plus heading, lateral position and the
neuromuscular filter (Hess, Moore & Hubbard 2012, "Modeling the manually controlled bicycle",
IEEE SMC-A 42(3):545-557; Moore 2012, dissertation, chapter "Control").

State (8): ``x = [roll, steer, roll', steer', heading psi, rear-contact lateral position yP,
T, T']`` with ``T`` the rider's steer torque, the output of the neuromuscular filter

    T'' + 2 zeta_nm w_nm T' + w_nm^2 T = w_nm^2 u,   w_nm = 30 rad/s, zeta_nm = 0.707.

Kinematics of the linear Whipple model (Meijaard et al. 2007, Sec 5; small angles, speed
held):

    psi' = cos(lam) (v steer + c steer') / w,   yP' = v psi,
    yQ = yP + w psi - c cos(lam) steer   (front-wheel contact, the tracked point)

with wheelbase ``w``, trail ``c``, steer-axis tilt ``lam`` of the model's bicycle.

The rider's control ``u`` (N m) closes five nested loops (outer to inner):
``psi_c = kY (yc - yQ)``, ``phi_c = kPsi (psi_c - psi)``, ``phidot_c = kPhi (phi_c - phi)``,
``delta_c = kPhiDot (phidot_c - roll')``, ``u = kDelta (delta_c - steer)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..linear import state_matrix
from ..params import LinearModel

__all__ = [
    "NEURO_FREQ_RAD_S", "NEURO_DAMPING", "LOOPS", "GAIN_NAMES", "STATES", "N_STATES", "Geometry",
    "Plant", "CONTROL_INPUTS", "neuromuscular_filter", "plant", "control_law", "closed_matrix",
    "open_loop_response",
]

#: Neuromuscular natural frequency (rad/s) and damping ratio (Hess et al. 2012).
NEURO_FREQ_RAD_S = 30.0
NEURO_DAMPING = 0.707

#: Loop names, inner to outer, and the gain names.
LOOPS: tuple[str, ...] = ("Delta", "PhiDot", "Phi", "Psi", "Y")
GAIN_NAMES: tuple[str, ...] = tuple(f"k{name}" for name in LOOPS)
#: State names of :func:`plant`.
STATES: tuple[str, ...] = ("roll", "steer", "roll_rate", "steer_rate", "heading", "y_rear",
                           "torque", "torque_rate")
N_STATES = len(STATES)


@dataclass(frozen=True)
class Geometry:
    """Wheelbase ``w_m``, trail ``c_m`` and steer-axis tilt ``lam_rad`` (from vertical)."""

    w_m: float
    c_m: float
    lam_rad: float

    @classmethod
    def from_mapping(cls, g: dict[str, float]) -> Geometry:
        """From a benchmark-style mapping with keys ``w``, ``c``, ``lam``."""
        missing = [k for k in ("w", "c", "lam") if k not in g]
        if missing:
            raise KeyError(f"bicycle geometry lacks {missing} (need w, c, lam)")
        return cls(float(g["w"]), float(g["c"]), float(g["lam"]))


@dataclass(frozen=True)
class Plant:
    """Open-loop plant ``x' = A x + B_u u + B_f f`` with outputs of the five loops.

    Attributes
    ----------
    A
        (8, 8) state matrix (neuromuscular filter included, loops open).
    B_u
        (8,) input of the rider's command ``u`` (N m) into the filter.
    B_f
        (8, 2) input of external roll and steer torques ``f`` (N m, Eq 3.1 right-hand side).
    C
        (5, 8) outputs ``[steer, roll', roll, psi, yQ]`` (the loops' fed-back variables,
        inner to outer, :data:`LOOPS`).
    """

    A: np.ndarray
    B_u: np.ndarray
    B_f: np.ndarray
    C: np.ndarray
    speed_m_s: float
    control_input: str = "steer"


#: The rider's control inputs: steer torque (hands on) or roll torque (HumanControl's "Roll"
#: input, a hands-free stand-in: an external torque about the roll axis).
CONTROL_INPUTS: tuple[str, ...] = ("steer", "roll")


def neuromuscular_filter(a: np.ndarray, first: int, neuro_freq_rad_s: float,
                         neuro_damping: float) -> np.ndarray:
    """Write the rider's second-order neuromuscular filter into state matrix ``a`` (in place)
    and return its input column.

    The filter's states are ``first`` (the torque, T) and ``first + 1`` (its rate):
    :math:`T'' + 2\\zeta_{nm}\\omega_{nm} T' + \\omega_{nm}^2 T = \\omega_{nm}^2 u`
    (Hess, Moore and Hubbard 2012).

    Parameters
    ----------
    a
        The plant's state matrix, square; rows ``first`` and ``first + 1`` are written.
    first
        Index of the filter's torque state.
    neuro_freq_rad_s, neuro_damping
        :math:`\\omega_{nm}` (rad/s) and :math:`\\zeta_{nm}`.

    Returns
    -------
    numpy.ndarray
        The input column ``b_u`` of the rider's command ``u`` (length ``a.shape[0]``).
    """
    wn, z = float(neuro_freq_rad_s), float(neuro_damping)
    a[first, first + 1] = 1.0
    a[first + 1, first] = -wn**2
    a[first + 1, first + 1] = -2.0 * z * wn
    b_u = np.zeros(a.shape[0])
    b_u[first + 1] = wn**2
    return b_u


def plant(model: LinearModel, geometry: Geometry, speed_m_s: float,
          neuro_freq_rad_s: float = NEURO_FREQ_RAD_S,
          neuro_damping: float = NEURO_DAMPING, control_input: str = "steer") -> Plant:
    """The rider-control plant of ``model`` at one speed (module docstring).

    Parameters
    ----------
    model
        Linear model of Eq 3.1 (benchmark or Appendix B).
    geometry
        The bicycle's ``w``, ``c``, ``lam``.
    speed_m_s
        Forward speed (m/s).
    neuro_freq_rad_s, neuro_damping
        The neuromuscular filter (Hess et al. 2012: 30 rad/s, 0.707).
    control_input
        ``"steer"``: the filter's torque acts on the steer equation; ``"roll"``: on the roll
        equation, and the steer angle is not fed back (``C[0] = 0``, use ``kDelta = 1``), as
        HumanControl's ``input='Roll'``.
    """
    if control_input not in CONTROL_INPUTS:
        raise ValueError(f"control_input {control_input!r}: expected one of {CONTROL_INPUTS}")
    v = float(speed_m_s)
    a = np.zeros((N_STATES, N_STATES))
    a[0:4, 0:4] = state_matrix(model, v)
    minv = np.linalg.inv(model.M)
    a[2:4, 6] = minv[:, 1 if control_input == "steer" else 0]
    cl, w, c = np.cos(geometry.lam_rad), geometry.w_m, geometry.c_m
    a[4, 1] = v * cl / w
    a[4, 3] = c * cl / w
    a[5, 4] = v
    b_u = neuromuscular_filter(a, 6, neuro_freq_rad_s, neuro_damping)
    b_f = np.zeros((N_STATES, 2))
    b_f[2:4, :] = minv
    cmat = np.zeros((5, N_STATES))
    cmat[0, 1] = 1.0 if control_input == "steer" else 0.0  # steer
    cmat[1, 2] = 1.0  # roll rate
    cmat[2, 0] = 1.0  # roll
    cmat[3, 4] = 1.0  # heading
    cmat[4, 5] = 1.0  # yQ = yP + w psi - c cos(lam) steer
    cmat[4, 4] = w
    cmat[4, 1] = -c * cl
    return Plant(a, b_u, b_f, cmat, v, control_input)


def control_law(p: Plant, gains: np.ndarray, outer: int = 5) -> tuple[np.ndarray, float]:
    """The rider's command ``u = K x + k_r r`` with loops ``0 .. outer-1`` closed.

    Any plant with five loop outputs ``C`` (5, n) works: this 8-state one or the 10-state
    leaning-rider plant of :func:`pedalrepro.rider.lean.lean_plant`.

    ``r`` is the command entering loop ``outer - 1`` (``yc`` when all five loops are closed);
    for the open-loop transfer function of loop ``j`` call with ``outer=j`` and the gains of
    loops ``< j``: ``r`` is then the (unit-gain) command of loop ``j - 1``.

    Returns
    -------
    K, k_r
        (8,) feedback row and the command gain.
    """
    g = np.asarray(gains, float)
    k = np.zeros(p.A.shape[0])
    k_r = 1.0
    # c_{l-1} = g_l (c_l - y_l) from loop outer-1 down to 0
    for level in range(outer - 1, -1, -1):
        k = g[level] * (k - p.C[level])
        k_r = g[level] * k_r
    return k, k_r


def closed_matrix(p: Plant, gains: np.ndarray, outer: int = 5) -> np.ndarray:
    """State matrix with loops ``0 .. outer-1`` closed (:func:`control_law`), (n, n)."""
    k, _ = control_law(p, gains, outer)
    return p.A + np.outer(p.B_u, k)


def open_loop_response(p: Plant, gains: np.ndarray, loop: int,
                       frequency_rad_s: np.ndarray) -> np.ndarray:
    """Open-loop transfer function of loop ``loop`` (0 = Delta .. 4 = Y) at ``j w``.

    The loops inside it are closed with ``gains``, the loop itself is broken with unit gain:
    the response of its fed-back variable to its own error signal (HumanControl's
    ``find_open_gain`` with ``k = 1``).
    """
    a = closed_matrix(p, gains, loop)
    _, k_r = control_law(p, gains, loop)
    b = p.B_u * k_r
    w = np.atleast_1d(np.asarray(frequency_rad_s, float))
    n = p.A.shape[0]
    x = np.linalg.solve(1j * w[:, None, None] * np.eye(n) - a,
                        np.broadcast_to(b, (len(w), n))[..., None])[..., 0]
    return x @ p.C[loop]
