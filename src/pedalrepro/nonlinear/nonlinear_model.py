"""The numeric non-linear bicycle-rider model, :class:`NonlinearModel`: state derivative,
energy, linearisation.

State (6): ``x = [roll, pitch, steer, roll rate, rear wheel rate, steer rate]`` (rad, rad/s), the
three independent coordinates that enter the flat-ground dynamics and the three independent
speeds of the Whipple model (Sec 3.1.1.3). The five dependent speeds follow from the velocity
constraints ``A(q) u = 0``; the accelerations solve Kane's equations with the constraint forces
resolved by Lagrange multipliers::

    [ M  A^T ] [u']   [ F + Q ]
    [ A   0  ] [-l] = [  -b   ]

``Q`` holds the generalised forces of the roll torque (about the roll axis, between rear frame
and ground) and the steer torque (between rear and front frame), the ``T_phi``, ``T_delta`` of
Meijaard et al. (2007) and the generalised pedalling torques of Eq 3.14.

The Python reference (:meth:`NonlinearModel.rhs_python`) solves this 13 x 13 system; the
compiled right-hand side (``pedalrepro/csrc/model_rhs.h``) solves its null-space form, the
3 x 3 system of the independent accelerations (same solution, to rounding, in less time:
scripts/bench_nonlinear.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from . import codegen, library, symbolic
from .symbolic import PITCH, REAR_WHEEL, ROLL, STEER, U_DEP, U_IND

__all__ = [
    "ZERO_SPEC", "moore_parameters", "NonlinearModel",
    "benchmark_matrices",
]

ZERO_SPEC: Callable[[float], np.ndarray] | None = None


def moore_parameters(bench: dict[str, float]) -> dict[str, float]:
    """SymBRiM parameter values from benchmark parameters (Meijaard et al. 2007, Table 1).

    Moore's (2012) conversion, as SymBRiM's own ``get_param_values`` does through
    ``dtk.bicycle.benchmark_to_moore``: the rear-frame offset ``d1``, front offset ``d3`` and
    steer-axis length ``d2`` from wheelbase, trail, steer-axis tilt and wheel radii; the frame and
    fork mass centres along and normal to the steer axis (``l1, l2`` from the rear wheel centre,
    ``l3, l4`` from the front wheel centre); the frame and fork inertia rotated through the tilt
    ``R(lam) I R(lam)^T``. Written here, in dtk's order of operations, instead of imported: dtk's
    bicycle module imports ``matplotlib.pyplot`` and ``scipy.optimize`` (0.8 s of every job that
    builds a non-linear model); tests/nonlinear/test_nonlinear.py checks it equals dtk's to the
    bit.
    """
    need = {"w", "c", "lam", "g", "rR", "mR", "IRxx", "IRyy", "xB", "zB", "mB", "IBxx", "IByy",
            "IBzz", "IBxz", "xH", "zH", "mH", "IHxx", "IHyy", "IHzz", "IHxz", "rF", "mF", "IFxx",
            "IFyy"}
    missing = sorted(need - set(bench))
    if missing:
        raise KeyError(f"benchmark parameters missing: {missing}")
    b = bench
    lam = b["lam"]
    sin_l, cos_l, tan_l = math.sin(lam), math.cos(lam), math.tan(lam)
    d1 = cos_l * (b["c"] + b["w"] - b["rR"] * tan_l)
    d3 = -cos_l * (b["c"] - b["rF"] * tan_l)
    d2 = (b["rR"] + d1 * sin_l - b["rF"] + d3 * sin_l) / cos_l
    l1 = b["xB"] * cos_l - b["zB"] * sin_l - b["rR"] * sin_l
    l2 = b["xB"] * sin_l + b["zB"] * cos_l + b["rR"] * cos_l
    l4 = (b["zH"] + b["rF"]) * cos_l + (b["xH"] - b["w"]) * sin_l
    l3 = (b["xH"] - b["w"] - l4 * sin_l) / cos_l
    sa, ca = np.sin(lam), np.cos(lam)
    rot = np.array([[ca, 0.0, -sa], [0.0, 1.0, 0.0], [sa, 0.0, ca]])

    def tilted(body: str) -> np.ndarray:
        inertia = np.array([[b[f"I{body}xx"], 0.0, b[f"I{body}xz"]], [0.0, b[f"I{body}yy"], 0.0],
                            [b[f"I{body}xz"], 0.0, b[f"I{body}zz"]]])
        return rot @ inertia @ rot.T

    ic, ie = tilted("B"), tilted("H")
    return {
        "front_frame_body_mass": b["mH"], "front_frame_d2": d2,
        "front_frame_d3": d3, "front_frame_ixx": float(ie[0, 0]),
        "front_frame_iyy": float(ie[1, 1]), "front_frame_izz": float(ie[2, 2]),
        "front_frame_izx": float(ie[2, 0]), "front_frame_l3": l3, "front_frame_l4": l4,
        "front_wheel_ixx": b["IFxx"], "front_wheel_iyy": b["IFyy"],
        "front_wheel_mass": b["mF"], "front_wheel_r": b["rF"], "g": b["g"],
        "rear_frame_body_mass": b["mB"], "rear_frame_d1": d1,
        "rear_frame_ixx": float(ic[0, 0]), "rear_frame_iyy": float(ic[1, 1]),
        "rear_frame_izz": float(ic[2, 2]), "rear_frame_izx": float(ic[2, 0]),
        "rear_frame_l1": l1, "rear_frame_l2": l2,
        "rear_wheel_ixx": b["IRxx"], "rear_wheel_iyy": b["IRyy"],
        "rear_wheel_mass": b["mR"], "rear_wheel_r": b["rR"],
    }


@dataclass
class NonlinearModel:
    """A parametrised non-linear model ready for integration.

    Parameters
    ----------
    bench
        Benchmark parameters of the bicycle with the rigid part of the rider in body B.
    options
        Symbolic model options (prescribed legs or not).
    leg_parameters
        With legs: lateral position ``<body>_y`` (m), mass ``<body>_m`` (kg) and transverse
        moment of inertia ``<body>_I`` (kg m^2) of each body of :data:`symbolic.LEG_BODIES`.
    spec
        With legs: ``t -> s`` the prescribed motion (positions, rates, accelerations; the
        order of the generated ``SPEC`` list).
    arm_parameters
        With arms (``options.arms``): the values of :data:`symbolic.ARM_PARAMETERS`
        (:func:`pedalrepro.nonlinear.bodies.model_bodies`).
    steer_limit_rad
        Runs end like a fall when ``|steer|`` reaches this angle (arm loops: beyond it the arms
        cannot reach the handlebar, :func:`pedalrepro.nonlinear.arms.steer_reach_rad`).
    """

    bench: dict[str, float]
    options: symbolic.ModelOptions = field(default_factory=symbolic.ModelOptions)
    leg_parameters: dict[str, float] = field(default_factory=dict)
    spec: Callable[[float], np.ndarray] | None = None
    arm_parameters: dict[str, float] = field(default_factory=dict)
    steer_limit_rad: float = float("inf")

    compiled: bool = True

    def __post_init__(self) -> None:
        self._code = codegen.load(self.options)
        self.lib = library.load_library(self.options) if self.compiled else None
        values = moore_parameters(self.bench) | self.leg_parameters | self.arm_parameters
        missing = [n for n in self._code.PARAMS if n not in values]
        if missing:
            raise KeyError(f"parameters missing for the non-linear model: {missing}")
        self.p = [float(values[n]) for n in self._code.PARAMS]
        self.n_spec = len(self._code.SPEC)
        if self.n_spec and self.spec is None:
            raise ValueError("a model with prescribed legs needs spec(t)")
        self._zero_spec = [0.0] * self.n_spec
        self._zero_spec_arr = np.zeros(max(self.n_spec, 1))
        self.p_array = np.ascontiguousarray(self.p, dtype=float)

    # -- geometry -----------------------------------------------------------------------------
    @property
    def nominal_pitch_rad(self) -> float:
        """Rear-frame pitch of the upright, straight-ahead configuration: the steer-axis tilt."""
        return float(self.bench["lam"])

    def upright_state(self, speed_m_s: float, roll_rate_rad_s: float = 0.0,
                      steer_rate_rad_s: float = 0.0) -> np.ndarray:
        """Upright straight-ahead state at forward speed ``speed_m_s`` (rear wheel rolling)."""
        return np.array([0.0, self.nominal_pitch_rad, 0.0, roll_rate_rad_s,
                         -speed_m_s / self.bench["rR"], steer_rate_rad_s])

    # -- evaluation ---------------------------------------------------------------------------
    def _spec(self, t: float) -> list:
        return list(self.spec(t)) if self.spec is not None else self._zero_spec

    def _split(self, x):
        q = [0.0] * 8
        q[ROLL], q[PITCH], q[STEER] = x[0], x[1], x[2]
        return q

    def speeds(self, x, s=None, complex_step: bool = False) -> tuple[list, np.ndarray]:
        """Coordinates and all eight speeds (dependent ones from ``A(q) u = 0``)."""
        code = codegen.load(self.options, complex_step) if complex_step else self._code
        q = self._split(x)
        u = [0.0] * 8
        u[ROLL], u[REAR_WHEEL], u[STEER] = x[3], x[4], x[5]
        s = self._zero_spec if s is None else s
        parts = code.rhs_parts(q, u, self.p, s)
        A = np.array(parts[72:112]).reshape(5, 8)
        dep = np.linalg.solve(A[:, list(U_DEP)], -A[:, list(U_IND)] @ np.array(
            [x[3], x[4], x[5]]))
        u = np.array(u, dtype=dep.dtype)
        u[list(U_DEP)] = dep
        return q, u

    def accelerations(self, t: float, x, torque=(0.0, 0.0), complex_step: bool = False):
        """All eight speed derivatives ``u'`` and the speeds ``u`` at state ``x``."""
        code = codegen.load(self.options, complex_step) if complex_step else self._code
        s = self._spec(t)
        q, u = self.speeds(x, s, complex_step)
        parts = code.rhs_parts(q, list(u), self.p, s)
        M = np.array(parts[:64]).reshape(8, 8)
        F = np.array(parts[64:72])
        A = np.array(parts[72:112]).reshape(5, 8)
        b = np.array(parts[112:117])
        F = F.astype(np.result_type(F, torque[0], torque[1]))
        F[ROLL] += torque[0]
        F[STEER] += torque[1]
        K = np.zeros((13, 13), dtype=np.result_type(M, A))
        K[:8, :8] = M
        K[:8, 8:] = A.T
        K[8:, :8] = A
        sol = np.linalg.solve(K, np.concatenate([F, -b]))
        return sol[:8], u

    def rhs(self, t: float, x, torque=(0.0, 0.0)) -> np.ndarray:
        """State derivative ``x'`` (the equations of motion in first-order form).

        Uses the compiled library when available (:func:`library.compiled_library`), else the
        generated Python (:meth:`rhs_python`, the reference).
        """
        if self.lib is None:
            return self.rhs_python(t, x, torque)
        s = self.spec(t) if self.spec is not None else self._zero_spec_arr
        xa = np.ascontiguousarray(x, dtype=float)
        out = np.empty(6)
        status = self.lib.full_rhs(xa.ctypes.data, self.p_array.ctypes.data,
                                    np.ascontiguousarray(s, dtype=float).ctypes.data,
                                    float(torque[0]), float(torque[1]), out.ctypes.data, None)
        if status == 3:
            out[:] = np.nan  # the caller (simulate) reports non-finite states
        elif status:
            raise ZeroDivisionError(f"singular constraint/mass matrix at t = {t} (state {x})")
        return out

    def rhs_python(self, t: float, x, torque=(0.0, 0.0)) -> np.ndarray:
        """State derivative from the generated Python code (reference implementation)."""
        ud, u = self.accelerations(t, x, torque)
        return np.array([u[ROLL], u[PITCH], u[STEER], ud[ROLL], ud[REAR_WHEEL], ud[STEER]])

    def energy_J(self, t: float, x) -> float:
        """Total mechanical energy (kinetic + gravitational potential), J."""
        s = self._spec(t)
        q, u = self.speeds(x, s)
        return float(self._code.energy(q, list(u), self.p, s))

    def energy_drift(self, t_s, states) -> tuple[float, np.ndarray]:
        """Largest relative change of the total energy over a run, and the energies (J).

        ``t_s`` (n,) and ``states`` (6, n) as in :class:`pedalrepro.integrator.Simulation`. With no
        dissipation and scleronomic constraints the energy is constant (Sec 3.1.1.3 check). A run
        that ended early (fall, steer limit) has NaN samples after its end: the energies are
        those of the simulated samples.
        """
        states = np.asarray(states)
        simulated = np.all(np.isfinite(states), axis=0)
        if simulated.sum() < 2:
            raise ValueError("energy drift: fewer than two simulated samples")
        energy = np.array([self.energy_J(t, states[:, k]) for k, t in enumerate(t_s)
                           if simulated[k]])
        return float(np.max(np.abs(energy - energy[0])) / abs(energy[0])), energy

    # -- linearisation ------------------------------------------------------------------------
    def _complex_rhs(self, x, torque):
        ud, u = self.accelerations(0.0, x, torque, complex_step=True)
        return np.array([u[ROLL], u[PITCH], u[STEER], ud[ROLL], ud[REAR_WHEEL], ud[STEER]])

    def state_jacobian(self, speed_m_s: float, h: float = 1e-30) -> tuple[np.ndarray, np.ndarray]:
        """Exact (complex-step) Jacobians of ``x'`` w.r.t. state and torques at upright motion.

        Returns
        -------
        (J, B)
            ``J`` (6 x 6) = d x'/d x, ``B`` (6 x 2) = d x'/d [T_roll, T_steer].
        """
        if self.n_spec:
            raise ValueError("linearise the model without prescribed legs")
        x0 = self.upright_state(speed_m_s).astype(complex)
        J = np.zeros((6, 6))
        for k in range(6):
            dx = x0.copy()
            dx[k] += 1j * h
            J[:, k] = self._complex_rhs(dx, (0.0, 0.0)).imag / h
        B = np.zeros((6, 2))
        for k in range(2):
            tq = [0.0, 0.0]
            tq[k] = 1j * h
            B[:, k] = self._complex_rhs(x0, tuple(tq)).imag / h
        return J, B


def benchmark_matrices(nl: NonlinearModel, speeds_m_s=(0.0, 1.0)) -> dict[str, np.ndarray]:
    """``M, C1, K0, K2`` of the linearised roll-steer equations (Eq 3.1) from the non-linear model.

    The complex-step Jacobian at upright straight-ahead motion gives, for ``q = [roll, steer]``,
    ``q'' = -M^-1 (v C1 q' + (g K0 + v^2 K2) q) + M^-1 f``: ``M`` is the inverse of the torque
    block, ``C(v) = v C1`` and ``K(v) = g K0 + v^2 K2`` follow from two speeds (exact: they are
    polynomials of those degrees in ``v``).
    """
    g = nl.bench["g"]
    qi, ui = [0, 2], [3, 5]  # roll, steer in the state; their rates
    out = {}
    ks, cs = [], []
    for v in speeds_m_s:
        J, B = nl.state_jacobian(v)
        Minv = B[ui, :]
        M = np.linalg.inv(Minv)
        ks.append(-M @ J[np.ix_(ui, qi)])
        cs.append(-M @ J[np.ix_(ui, ui)])
        out["M"] = M
    v0, v1 = speeds_m_s
    out["K2"] = (ks[1] - ks[0]) / (v1**2 - v0**2)
    out["K0"] = (ks[0] - v0**2 * out["K2"]) / g
    out["C1"] = cs[1] / v1 if v1 else cs[0] / v0
    return out
