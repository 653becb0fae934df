"""Periodic pedalling responses of the non-linear models: shooting, Floquet multipliers and
continuation (beyond the thesis).

The thesis estimates the pedalling response of its non-linear models (methods NT and NP,
Sec 3.1.2.1) from 180 s simulations reduced by a Hann-windowed DFT; where the bicycle is
unstable the runs fall and the estimate breaks down. Its own recommendation (Sec 3.2.4) is
numerical continuation of the periodic solutions (Doedel et al. 2003). This module computes
those solutions directly.

Problem. The forcing has period ``T = 2 pi / omega`` (NT: the harmonic torques of Eq 3.14; NP:
the prescribed leg motion). The reduced state is ``y = [roll, pitch, steer, roll rate, steer
rate]``; the ignorable coordinates (position, yaw, wheel angles) are left out and pitch is a
function of roll and steer (the holonomic ground contact: :func:`po_pitch` in the C driver
integrates the pitch rate of the velocity constraints from upright). The orbit's unknowns are
the lateral states ``z = [roll, steer, roll rate, steer rate]``.

Forward speed. In the non-linear model the rear-wheel rate is a free state and the forcing
feeds it (a few 1e-4 m/s per period at 5 m/s), so no exactly periodic motion exists. **Choice:**
the speed is held by a generalised force on the rear-wheel rotation (a hub torque), computed at
every instant so that the rear-wheel acceleration is zero: the constant forward speed that the
linearised models (Eq 3.1) and the particular solution (PS, Eq 3.10-3.15) assume. Its mean over
the orbit is reported (``hold_torque_mean_nm``).

Shooting. Newton on ``z`` at ``m`` nodes (``m = 1``: single shooting; ``m > 1``: multiple
shooting with the segment length scaled so that the linear growth per segment stays below
``max_growth``). With odd harmonics only (NT's w, 3w, 5w; NP's mirror-symmetric leg motion) the
orbit has the symmetry ``z(t + T/2) = -z(t)``, so the shooting covers half a period with the
end condition ``-z(T/2) = z(0)``: half the cost, and the capsize multiplier (+1 over a full
period) becomes -1 over the half period, keeping Newton regular there. Segment Jacobians come
from the variational equations (forward differences of the compiled right-hand side along the
variational columns); their product is the monodromy matrix, whose eigenvalues (squared for the
half period) are the Floquet multipliers. The cadence-harmonic amplitude and phase of the orbit
are exact Fourier quadratures integrated with the state (``x ~ Re(c e^{i w t})``, the PS
convention of :func:`pedalrepro.response.particular_solution`).

Continuation. :func:`continue_branch` follows a branch in speed, or for NT in cadence or torque
scale (where folds appear at large torques near the weave resonance), with a secant predictor
and a pseudo-arclength corrector, and marks where a Floquet multiplier crosses the unit circle.
"""

from __future__ import annotations

import ctypes
import math
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import linear, response
from .integrator import build
from .params import LinearModel

if TYPE_CHECKING:
    import pandas as pd

#: Thesis speed range of the maps (Sec 3.1.2.2.1), m/s; the command line accepts this range.
SPEED_RANGE_M_S: tuple[float, float] = (0.0, 10.0)
#: Cadence range accepted by the command line, rpm (the thesis maps reach 4 pi rad/s = 120 rpm).
CADENCE_RANGE_RPM: tuple[float, float] = (1.0, 120.0)
METHODS: tuple[str, ...] = ("NT", "NP")
#: Lateral components of the reduced state y = [roll, pitch, steer, roll rate, steer rate].
LATERAL = (0, 2, 3, 4)


class ConvergenceError(RuntimeError):
    """Newton did not converge; ``residual`` is the smallest periodicity residual reached."""

    def __init__(self, message: str, residual: float) -> None:
        super().__init__(message)
        self.residual = residual


# ---------------------------------------------------------------------------------------------
# Adapter: the only place that touches pedalrepro.nonlinear (models, linearisation, generated C)
# ---------------------------------------------------------------------------------------------

_DRIVER = Path(__file__).with_name("periodic_driver.c")


class _Adapter:
    """Models, their own linearisation and the compiled periodic driver of a model variant."""

    @staticmethod
    def models() -> tuple[str, ...]:
        """The four models of the thesis; each has a non-linear counterpart."""
        from .params import MODELS

        return tuple(MODELS)

    @staticmethod
    @cache
    def nt_model(name: str):
        from .nonlinear import sweep

        return sweep.nt_model(name)

    @staticmethod
    def np_model(name: str, omega_rad_s: float):
        from .nonlinear import sweep

        return sweep.np_model(name, omega_rad_s)

    @staticmethod
    @cache
    def own_linearisation(name: str) -> LinearModel:
        """Eq 3.1 matrices of the NT model linearised about upright motion (complex step)."""
        from .nonlinear import numeric

        nl = _Adapter.nt_model(name)
        mats = numeric.benchmark_matrices(nl)
        return LinearModel(f"{name} (own linearisation)", mats["M"], mats["C1"], mats["K0"],
                           mats["K2"], float(nl.bench["g"]))

    @staticmethod
    def indices() -> dict[str, tuple[int, ...]]:
        from .nonlinear import model

        return {"iq": (model.ROLL, model.PITCH, model.STEER),
                "iu": (model.ROLL, model.REAR_WHEEL, model.STEER),
                "idep": tuple(model.U_DEP)}

    @staticmethod
    def generated_c(nl) -> str:
        """C source with the model's generated ``constraint_matrix`` and ``dynamics``."""
        from .nonlinear import codegen

        return Path(codegen.generated_c(nl.options)).read_text()

    @staticmethod
    @cache
    def forcing_struct() -> type[ctypes.Structure]:
        """``po_forcing`` of :file:`periodic_driver.c`: the model driver's ``forcing_t``
        (:class:`pedalrepro.nonlinear.simulate.ForcingStruct`, its fields reached directly
        through ctypes ``_anonymous_``) followed by the periodic driver's own."""
        from .nonlinear.simulate import ForcingStruct

        class Forcing(ctypes.Structure):
            _anonymous_ = ("f",)
            _fields_ = [("f", ForcingStruct), ("u_rear", ctypes.c_double),
                        ("omega_q", ctypes.c_double), ("iq", ctypes.c_int * 3),
                        ("iu", ctypes.c_int * 3), ("idep", ctypes.c_int * 5),
                        ("fd_step", ctypes.c_double), ("central", ctypes.c_int)]

        return Forcing

    @staticmethod
    @cache
    def library(model_c: str) -> ctypes.CDLL:
        """Model C + :file:`periodic_driver.c`, compiled once into the model cache folder."""
        from .nonlinear import codegen
        from .nonlinear.library import FORCING_C

        src = "\n".join([model_c, FORCING_C.read_text(), _DRIVER.read_text()])
        so = build.build(src, Path(codegen.cache_dir()), "periodic")
        if so is None:
            raise RuntimeError("no C compiler for the periodic driver")
        lib = ctypes.CDLL(str(so))
        dp, ci, cd = ctypes.c_void_p, ctypes.c_int, ctypes.c_double
        lib.po_rhs.argtypes = [dp, cd, dp, dp, dp]
        lib.po_rhs.restype = ci
        lib.po_pitch.argtypes = [dp, cd, cd, cd, ci, dp, dp]
        lib.po_pitch.restype = ci
        lib.po_flow.argtypes = [dp, cd, cd, dp, ci, cd, dp, dp, dp, ctypes.POINTER(ctypes.c_long),
                                ctypes.POINTER(cd)]
        lib.po_flow.restype = ci
        return lib


_FLOW_ERRORS = {-1: "non-finite state or singular system", -2: "step size underflow",
                -3: "too many steps", -4: "too many variational columns"}


# ---------------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------------

@dataclass
class Orbit:
    """A periodic orbit (or the last Newton iterate when ``converged`` is False).

    Amplitudes and phases are those of the cadence harmonic, ``x(t) ~ Re(A e^{i(w t + phase)})``
    with the forcing's time origin (as PS). ``floquet_multipliers`` are over a full period,
    sorted by decreasing modulus; ``periodicity_residual`` is the max-norm of the shooting
    equations (rad, rad/s) at the returned nodes.
    """

    model: str
    method: str
    speed_m_s: float
    omega_rad_s: float
    torque_scale: float
    nodes: np.ndarray
    roll_amplitude_rad: float
    steer_amplitude_rad: float
    roll_phase_rad: float
    steer_phase_rad: float
    floquet_multipliers: np.ndarray
    periodicity_residual: float
    converged: bool
    iterations: int
    segments: int
    half_period: bool
    peak_roll_rad: float
    peak_steer_rad: float
    hold_torque_mean_nm: float
    n_rhs: int
    monodromy: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((4, 4)))
    failure: str = ""

    @property
    def stable(self) -> bool:
        """All Floquet multipliers inside the unit circle."""
        return bool(np.max(np.abs(self.floquet_multipliers)) < 1.0)

    def summary(self) -> dict:
        """JSON-ready summary (the ``pedalrepro periodic`` output)."""
        out = {k: v for k, v in asdict(self).items() if k not in (
            "nodes", "monodromy", "floquet_multipliers", "failure")}
        out["cadence_rpm"] = self.omega_rad_s * 60.0 / (2.0 * np.pi)
        out["floquet_multipliers_abs"] = [float(x) for x in np.abs(self.floquet_multipliers)]
        out["floquet_multipliers_angle_rad"] = [float(x) for x in
                                                np.angle(self.floquet_multipliers)]
        out["stable"] = self.stable
        return {k: (float(v) if isinstance(v, np.floating) else v) for k, v in out.items()}


# ---------------------------------------------------------------------------------------------
# The shooting problem of one model, method and cadence
# ---------------------------------------------------------------------------------------------

class OrbitSolver:
    """Periodic orbits of one model and method at one cadence, for any forward speed.

    Parameters
    ----------
    model
        ``HS``, ``CF``, ``HR`` or ``CR`` (the non-linear models, Sec 3.1.1.3).
    method
        ``NT`` (legs fixed, harmonic torques of Eq 3.14) or ``NP`` (prescribed leg motion).
    omega_rad_s
        Cadence (rad/s); the forcing period is ``2 pi / omega``.
    torque_scale
        Factor on the NT torques (1e-3: the linear limit); NP accepts only 1.
    harmonics
        Torque harmonics of NT (Eq 3.14-3.15).
    rtol
        Relative local error tolerance of the integration; absolute tolerances are ``rtol``
        times the scale of the PS start.
    max_growth
        Largest linear growth factor ``exp(max Re(lambda) t)`` over one shooting segment.
    fd_step, central
        Relative step of the differences of the variational equations (default 1.5e-8
        forward, 1e-6 central) and whether they are central (twice the cost, error ~1e-12
        instead of ~1e-8).
    half_period
        Shoot over half a period with the odd symmetry ``z(t + T/2) = -z(t)`` (default: when
        the right-hand side has that symmetry, checked numerically); False: a full period.
    """

    def __init__(self, model: str, method: str, omega_rad_s: float, *, torque_scale: float = 1.0,
                 harmonics: tuple[int, ...] = (1, 3, 5), rtol: float = 1e-9,
                 max_growth: float = 100.0, fd_step: float | None = None,
                 central: bool = False, half_period: bool | None = None) -> None:
        if model not in _Adapter.models():
            raise ValueError(f"unknown model {model!r}: expected one of {_Adapter.models()}")
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}: expected one of {METHODS}")
        if not (omega_rad_s > 0 and math.isfinite(omega_rad_s)):
            raise ValueError(f"cadence must be positive and finite, got {omega_rad_s} rad/s")
        if method == "NP" and torque_scale != 1.0:
            raise ValueError("torque_scale applies to NT only (NP has no torques)")
        self.model, self.method = model, method
        self.omega_rad_s = float(omega_rad_s)
        self.period_s = 2.0 * np.pi / self.omega_rad_s
        self.torque_scale = float(torque_scale)
        self.rtol, self.max_growth = float(rtol), float(max_growth)
        self.linear = _Adapter.own_linearisation(model)
        harm = response.forcing(model, harmonics=tuple(harmonics))
        self.harmonics = response.SimpleHarmonics(
            np.asarray(harm.n), np.asarray(harm.roll) * self.torque_scale,
            np.asarray(harm.steer) * self.torque_scale)
        self.nl = (_Adapter.nt_model(model) if method == "NT"
                   else _Adapter.np_model(model, self.omega_rad_s))
        self.r_rear_m = float(self.nl.bench["rR"])
        self.pitch0_rad = float(self.nl.nominal_pitch_rad)
        self._lib = _Adapter.library(_Adapter.generated_c(self.nl))
        self._keep: list[np.ndarray] = []
        fc = _Adapter.forcing_struct()()
        fc.p = self._ptr(np.asarray(self.nl.p, float))
        if method == "NT":
            n = np.asarray(self.harmonics.n, float)
            w = n * self.omega_rad_s
            roll = np.asarray(self.harmonics.roll, complex) * w**2
            steer = np.asarray(self.harmonics.steer, complex) * w**2
            fc.n_harm = len(n)
            fc.harm_w, fc.roll_re, fc.roll_im = self._ptr(w), self._ptr(roll.real), self._ptr(
                roll.imag)
            fc.steer_re, fc.steer_im = self._ptr(steer.real), self._ptr(steer.imag)
        else:
            spec = self.nl.spec
            fc.n_spec, fc.n_four, fc.omega = self.nl.n_spec, spec.coef.shape[1], spec.omega_rad_s
            fc.four_re, fc.four_im = (self._ptr(a) for a in spec.harmonic_major())
            fc.slope = self._ptr(spec.slope)
        idx = _Adapter.indices()
        fc.iq[:], fc.iu[:], fc.idep[:] = idx["iq"], idx["iu"], idx["idep"]
        fc.omega_q = self.omega_rad_s
        fc.central = int(central)
        fc.fd_step = float(fd_step if fd_step is not None else (1e-6 if central else 1.5e-8))
        self._fc = fc
        symmetric = self._odd_symmetric()
        if half_period and not symmetric:
            raise ValueError(f"{model} {method}: the forcing is not odd-symmetric, so the "
                             "half-period shooting does not apply")
        self.half_period = symmetric if half_period is None else bool(half_period)
        self._h = ctypes.c_double(0.0)

    @property
    def shoot_s(self) -> float:
        """Length of the shooting interval: half the period with the odd symmetry, else T."""
        return self.period_s / 2 if self.half_period else self.period_s

    # -- low level ----------------------------------------------------------------------------
    def _ptr(self, a) -> int:
        a = np.ascontiguousarray(a, dtype=float)
        self._keep.append(a)
        return a.ctypes.data

    def set_speed(self, speed_m_s: float) -> None:
        """Hold the rear wheel at the rate of forward speed ``speed_m_s``."""
        self._fc.u_rear = -float(speed_m_s) / self.r_rear_m
        self.speed_m_s = float(speed_m_s)

    def rhs(self, t_s: float, y) -> tuple[np.ndarray, float]:
        """Reduced right-hand side ``y'`` and the speed-holding generalised force (N m)."""
        y = np.ascontiguousarray(y, float)
        dy, tau = np.empty(5), ctypes.c_double()
        status = self._lib.po_rhs(ctypes.byref(self._fc), float(t_s), y.ctypes.data,
                                  dy.ctypes.data, ctypes.byref(tau))
        if status:
            raise ZeroDivisionError(f"singular system at t = {t_s} s, state {y}")
        return dy, tau.value

    def state(self, z) -> tuple[np.ndarray, np.ndarray]:
        """Reduced state ``y`` on the ground-contact manifold for lateral state ``z``, and
        ``dy/dz`` (5 x 4)."""
        pitch, dp = ctypes.c_double(), np.empty(2)
        status = self._lib.po_pitch(ctypes.byref(self._fc), float(z[0]), float(z[1]),
                                    self.pitch0_rad, 16, ctypes.byref(pitch), dp.ctypes.data)
        if status:
            raise ZeroDivisionError(f"singular constraints at roll {z[0]}, steer {z[1]}")
        y = np.array([z[0], pitch.value, z[1], z[2], z[3]])
        dydz = np.zeros((5, 4))
        dydz[0, 0] = dydz[2, 1] = dydz[3, 2] = dydz[4, 3] = 1.0
        dydz[1, :2] = dp
        return y, dydz

    def _odd_symmetric(self) -> bool:
        """Whether ``f(S y, t + T/2) = S f(y, t)`` (S flips the lateral states) holds."""
        self.set_speed(5.0)
        rng = np.random.default_rng(0)
        for t in rng.uniform(0, self.period_s, 3):
            z = rng.normal(scale=0.05, size=4)
            y, _ = self.state(z)
            ym, _ = self.state(-z)
            f, _ = self.rhs(t, y)
            fm, _ = self.rhs(t + self.period_s / 2, ym)
            flip = np.array([-1.0, 1.0, -1.0, -1.0, -1.0])
            if np.max(np.abs(flip * fm - f)) > 1e-9 * max(1.0, np.max(np.abs(f))):
                return False
        return True

    def flow(self, t0_s: float, t1_s: float, z, *, variational: bool = True,
             atol: np.ndarray | None = None) -> dict:
        """Integrate from lateral state ``z`` at ``t0_s`` to ``t1_s`` (speed held).

        Returns ``z1`` (4,), ``G = dz1/dz`` (4 x 4, when ``variational``), the Fourier
        quadratures ``quad`` (roll cos, roll sin, steer cos, steer sin, holding force), ``peak``
        (max ``|roll|``, max ``|steer|``) and ``n_rhs``.
        """
        y, dydz = self.state(z)
        nvar = 4 if variational else 0
        Y0 = np.concatenate([y, dydz.T.ravel() if variational else [], np.zeros(5)])
        Y1 = np.empty_like(Y0)
        if atol is None:
            atol = self.rtol * np.maximum(np.abs(y), 1e-6)
        atol = np.ascontiguousarray(atol, float)
        peak, n = np.empty(2), ctypes.c_long()
        status = self._lib.po_flow(ctypes.byref(self._fc), float(t0_s), float(t1_s),
                                   Y0.ctypes.data, nvar, self.rtol, atol.ctypes.data,
                                   Y1.ctypes.data, peak.ctypes.data, ctypes.byref(n),
                                   ctypes.byref(self._h))
        if status:
            raise FloatingPointError(f"integration failed ({_FLOW_ERRORS.get(status, status)}) "
                                     f"at {self.speed_m_s} m/s, {self.omega_rad_s} rad/s")
        out = {"z1": Y1[list(LATERAL)], "quad": Y1[5 + 5 * nvar:], "peak": peak,
               "n_rhs": int(n.value)}
        if variational:
            V = Y1[5:5 + 20].reshape(4, 5).T  # column j = dy/dz_j
            out["G"] = V[list(LATERAL), :]
        return out

    # -- start and segments -------------------------------------------------------------------
    def ps_state(self, speed_m_s: float, t_s) -> np.ndarray:
        """Lateral state of the particular solution of the model's own linearisation (PS)."""
        roll, steer = response.particular_solution(self.linear, speed_m_s, self.omega_rad_s,
                                                   self.harmonics)
        w = np.asarray(self.harmonics.n, float) * self.omega_rad_s
        e = np.exp(1j * np.multiply.outer(np.atleast_1d(t_s), w))
        return np.stack([(e @ roll).real, (e @ steer).real, (e @ (1j * w * roll)).real,
                         (e @ (1j * w * steer)).real], axis=-1)

    def segments_for(self, speed_m_s: float) -> int:
        """Shooting segments so that the linear growth per segment stays below ``max_growth``."""
        rate = max(0.0, float(np.max(linear.eigenvalues(self.linear, speed_m_s).real)))
        return int(min(64, max(1, math.ceil(rate * self.shoot_s / math.log(self.max_growth)))))

    def node_times(self, m: int) -> np.ndarray:
        return np.arange(m + 1) * self.shoot_s / m

    # -- shooting -----------------------------------------------------------------------------
    def residual(self, nodes: np.ndarray, *, variational: bool = True,
                 atol: np.ndarray | None = None) -> dict:
        """Shooting equations at ``nodes`` (m x 4) and, with ``variational``, their Jacobian
        and the monodromy matrix of the shooting interval."""
        m = nodes.shape[0]
        t = self.node_times(m)
        sign = -1.0 if self.half_period else 1.0
        R = np.empty((m, 4))
        quad, peak, n_rhs = np.zeros(5), np.zeros(2), 0
        G = []
        for k in range(m):
            f = self.flow(t[k], t[k + 1], nodes[k], variational=variational, atol=atol)
            last = k == m - 1
            z1 = sign * f["z1"] if last else f["z1"]
            R[k] = z1 - nodes[0 if last else k + 1]
            quad += f["quad"]
            peak = np.maximum(peak, f["peak"])
            n_rhs += f["n_rhs"]
            if variational:
                G.append(sign * f["G"] if last else f["G"])
        out = {"R": R, "quad": quad, "peak": peak, "n_rhs": n_rhs}
        if variational:
            J = np.zeros((4 * m, 4 * m))
            H = np.eye(4)
            for k in range(m):
                J[4 * k:4 * k + 4, 4 * k:4 * k + 4] += G[k]
                nxt = 0 if k == m - 1 else k + 1
                J[4 * k:4 * k + 4, 4 * nxt:4 * nxt + 4] -= np.eye(4)
                H = G[k] @ H
            out["J"], out["H"] = J, H
        return out

    def solve(self, speed_m_s: float, start: np.ndarray | None = None, *,
              segments: int | None = None, max_iter: int = 12, tol: float = 1e-10,
              switch: float = 1e-6) -> Orbit:
        """Periodic orbit at ``speed_m_s`` by Newton from ``start`` (nodes) or the PS.

        ``segments``: 1 for single shooting; default :meth:`segments_for`. ``tol``: relative
        convergence tolerance on the max-norm residual (scaled by the orbit's size). The
        variational equations (Jacobian and monodromy) are integrated while the relative
        residual exceeds ``switch``; closer to the orbit the last Jacobian is reused (chord
        steps), so the Floquet multipliers belong to an iterate within ``switch`` of the orbit.
        Returns an :class:`Orbit` with ``converged`` False when Newton fails (never raises for
        that).
        """
        self.set_speed(speed_m_s)
        if start is not None:
            nodes = np.array(start, float).reshape(-1, 4)
            m = nodes.shape[0]
        else:
            m = segments or self.segments_for(speed_m_s)
            nodes = self.ps_state(speed_m_s, self.node_times(m)[:-1])
        scale = max(float(np.max(np.abs(nodes))), 1e-300)
        atol = self.rtol * np.array([scale, 1.0, scale, scale, scale])
        best_res, best_nodes, best_ev = np.inf, nodes, None
        jac = None
        total, it, ok, prev_res, why = 0, 0, False, np.inf, ""
        for it in range(max_iter + 1):
            need = jac is None or best_res > switch * scale
            try:
                ev = self.residual(nodes, variational=need, atol=atol)
            except (FloatingPointError, ZeroDivisionError) as exc:
                why = str(exc)
                break
            total += ev["n_rhs"]
            if need:
                jac = ev
            res = float(np.max(np.abs(ev["R"])))
            if not np.isfinite(res) or res > 1e3 * max(best_res, 1e-12 * scale):
                break
            if res < best_res:
                best_res, best_nodes, best_ev = res, nodes, ev
            if res <= tol * scale or (res <= 1e-9 and res > 0.5 * prev_res):
                ok = True  # converged, or stagnated at the integration's noise floor
                break
            prev_res = res
            if it == max_iter:
                break
            try:
                step = np.linalg.solve(jac["J"], -ev["R"].ravel()).reshape(m, 4)
            except np.linalg.LinAlgError:
                break
            nodes = nodes + step
        if best_ev is None or jac is None:
            out = self._failed(best_nodes, m, it, total)
        else:
            out = self._orbit(best_nodes, dict(best_ev, H=jac["H"]), best_res,
                              ok and best_res <= 1e-9, it, total)
        if not out.converged:
            out.failure = why or f"{it} Newton iterations"
        return out

    def _orbit(self, nodes, ev, res, ok, it, total) -> Orbit:
        c = 2.0 / self.shoot_s * (ev["quad"][[0, 2]] - 1j * ev["quad"][[1, 3]])
        mu = np.linalg.eigvals(ev["H"])
        if self.half_period:
            mu = mu**2
        mu = mu[np.argsort(-np.abs(mu))]
        return Orbit(self.model, self.method, self.speed_m_s, self.omega_rad_s, self.torque_scale,
                     nodes, float(abs(c[0])), float(abs(c[1])), float(np.angle(c[0])),
                     float(np.angle(c[1])), mu, res, bool(ok), it, nodes.shape[0],
                     self.half_period, float(ev["peak"][0]), float(ev["peak"][1]),
                     float(ev["quad"][4] / self.shoot_s), total, ev["H"])

    def _failed(self, nodes, m, it, total) -> Orbit:
        nan = float("nan")
        return Orbit(self.model, self.method, self.speed_m_s, self.omega_rad_s, self.torque_scale,
                     nodes, nan, nan, nan, nan, np.full(4, nan + 0j), float("inf"), False, it, m,
                     self.half_period, nan, nan, nan, total)


def orbit(model: str, method: str, speed_m_s: float, cadence_rad_s: float, **kw) -> Orbit:
    """One periodic orbit (:class:`OrbitSolver` ``(model, method, cadence).solve(speed)``).

    Raises
    ------
    ValueError
        Model, method, speed or cadence out of range.
    ConvergenceError
        Newton did not converge (the message gives the residual reached).
    """
    lo, hi = SPEED_RANGE_M_S
    if not lo <= speed_m_s <= hi:
        raise ValueError(f"speed_m_s = {speed_m_s} outside the thesis range [{lo}, {hi}] m/s")
    rpm = cadence_rad_s * 60.0 / (2.0 * np.pi)
    lo, hi = CADENCE_RANGE_RPM
    if not lo <= rpm <= hi:
        raise ValueError(f"cadence_rpm = {rpm:g} outside [{lo}, {hi}] rpm")
    segments = kw.pop("segments", None)
    solver = OrbitSolver(model, method, cadence_rad_s, **kw)
    out = solver.solve(speed_m_s, segments=segments)
    if not out.converged:
        raise ConvergenceError(
            f"Newton did not converge for {model} {method} at {speed_m_s} m/s, {rpm:g} rpm: "
            f"periodicity residual reached {out.periodicity_residual:.3g} ({out.failure}; "
            f"{out.segments} shooting segment(s): more segments help where the bicycle is "
            f"very unstable)", out.periodicity_residual)
    return out


# ---------------------------------------------------------------------------------------------
# Maps over the speed x cadence grid
# ---------------------------------------------------------------------------------------------

MAP_KEYS = ("roll_amp_rad", "steer_amp_rad", "roll_phase_rad", "steer_phase_rad",
            "max_multiplier_abs", "residual", "peak_roll_rad", "peak_steer_rad",
            "hold_torque_mean_nm", "orbit_time_s", "orbit_cpu_s", "ps_roll_amp_rad",
            "ps_steer_amp_rad")


def orbit_map(model: str, method: str, speeds_m_s, omegas_rad_s, *, rtol: float = 1e-9,
              max_growth: float = 100.0, torque_scale: float = 1.0) -> dict[str, np.ndarray]:
    """Periodic orbits on ``speeds x omegas`` (the maps of Fig 3.35/G.7 for the non-linear
    models).

    Each point starts from the PS of the model's own linearisation; a failed point is retried
    with twice the shooting segments and then from the converged neighbour at the next lower
    speed. Zero cadence (no forcing) gives zero amplitude and NaN multipliers.

    Returns
    -------
    dict
        ``speed_m_s``, ``omega_rad_s`` and, on the grid, the arrays of :data:`MAP_KEYS`,
        ``multipliers`` (complex, (nv, nw, 4)), ``stable``, ``converged``, ``iterations``,
        ``segments``, ``half_period``, ``n_rhs``. ``ps_*``: PS amplitude at the cadence of the
        model's own linearisation (the linear reference of the same model).
    """
    import time

    v = np.asarray(speeds_m_s, float)
    w = np.asarray(omegas_rad_s, float)
    shape = (v.size, w.size)
    out = {k: np.full(shape, np.nan) for k in MAP_KEYS}
    out["multipliers"] = np.full(shape + (4,), np.nan + 0j)
    for k in ("stable", "converged", "half_period"):
        out[k] = np.zeros(shape, bool)
    for k in ("iterations", "segments", "n_rhs"):
        out[k] = np.zeros(shape, int)
    for j, wj in enumerate(w):
        if wj <= 0:
            for key in ("roll_amp_rad", "steer_amp_rad", "ps_roll_amp_rad", "ps_steer_amp_rad"):
                out[key][:, j] = 0.0
            out["converged"][:, j] = True
            continue
        solver = OrbitSolver(model, method, wj, rtol=rtol, max_growth=max_growth,
                             torque_scale=torque_scale)
        roll_ps, steer_ps = response.particular_solution(solver.linear, v, wj, solver.harmonics)
        first = int(np.flatnonzero(np.asarray(solver.harmonics.n) == 1)[0])
        out["ps_roll_amp_rad"][:, j] = np.abs(roll_ps[:, first])
        out["ps_steer_amp_rad"][:, j] = np.abs(steer_ps[:, first])
        previous: Orbit | None = None
        for i, vi in enumerate(v):
            t0, c0 = time.perf_counter(), time.process_time()
            orb = solver.solve(vi)
            if not orb.converged:
                orb = solver.solve(vi, segments=2 * orb.segments)
            if not orb.converged and previous is not None:
                orb = solver.solve(vi, start=previous.nodes)
            out["orbit_time_s"][i, j] = time.perf_counter() - t0
            out["orbit_cpu_s"][i, j] = time.process_time() - c0
            if orb.converged:
                previous = orb
            out["roll_amp_rad"][i, j] = orb.roll_amplitude_rad
            out["steer_amp_rad"][i, j] = orb.steer_amplitude_rad
            out["roll_phase_rad"][i, j] = orb.roll_phase_rad
            out["steer_phase_rad"][i, j] = orb.steer_phase_rad
            out["multipliers"][i, j] = orb.floquet_multipliers
            out["max_multiplier_abs"][i, j] = np.max(np.abs(orb.floquet_multipliers))
            out["residual"][i, j] = orb.periodicity_residual
            out["peak_roll_rad"][i, j] = orb.peak_roll_rad
            out["peak_steer_rad"][i, j] = orb.peak_steer_rad
            out["hold_torque_mean_nm"][i, j] = orb.hold_torque_mean_nm
            out["stable"][i, j] = orb.converged and orb.stable
            out["converged"][i, j] = orb.converged
            out["half_period"][i, j] = orb.half_period
            out["iterations"][i, j] = orb.iterations
            out["segments"][i, j] = orb.segments
            out["n_rhs"][i, j] = orb.n_rhs
            if not orb.converged:  # keep the residual reached, blank the orbit's values
                for key in ("roll_amp_rad", "steer_amp_rad", "roll_phase_rad", "steer_phase_rad",
                            "max_multiplier_abs", "peak_roll_rad", "peak_steer_rad",
                            "hold_torque_mean_nm"):
                    out[key][i, j] = np.nan
    out["speed_m_s"], out["omega_rad_s"] = v, w
    return out


# ---------------------------------------------------------------------------------------------
# Continuation
# ---------------------------------------------------------------------------------------------

@dataclass
class Branch:
    """A continued branch of periodic orbits.

    ``parameter`` is ``"speed_m_s"`` or ``"omega_rad_s"``; arrays run along the branch (in
    arclength order, so a fold shows as a parameter that turns back). ``crossings``: where the
    number of Floquet multipliers outside the unit circle changes, with the parameter value
    (interpolated in ``log |mu|``) and the kind of crossing (``+1``, ``-1`` or ``complex``).
    """

    model: str
    method: str
    parameter: str
    fixed: float
    values: np.ndarray
    roll_amp_rad: np.ndarray
    steer_amp_rad: np.ndarray
    multipliers: np.ndarray
    residual: np.ndarray
    crossings: list[dict]

    @property
    def stable(self) -> np.ndarray:
        return np.max(np.abs(self.multipliers), axis=1) < 1.0

    def arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The branch as arrays (for ``np.savez``)."""
        c = self.crossings
        return {f"{prefix}values": self.values, f"{prefix}roll_amp_rad": self.roll_amp_rad,
                f"{prefix}steer_amp_rad": self.steer_amp_rad,
                f"{prefix}multipliers": self.multipliers, f"{prefix}residual": self.residual,
                f"{prefix}stable": self.stable,
                f"{prefix}crossing_values": np.array([x["value"] for x in c], float),
                f"{prefix}crossing_kinds": np.array([x["kind"] for x in c], dtype="U8")}


def _crossing_kind(mu: complex) -> str:
    ang = abs(float(np.angle(mu)))
    return "+1" if ang < 1e-3 else ("-1" if ang > np.pi - 1e-3 else "complex")


def _crossings(values: np.ndarray, mus: np.ndarray) -> list[dict]:
    out = []
    n_out = np.sum(np.abs(mus) > 1.0, axis=1)
    for i in range(len(values) - 1):
        if n_out[i] == n_out[i + 1]:
            continue
        # the multiplier nearest the unit circle after the change
        k = int(np.argmin(np.abs(np.log(np.abs(mus[i + 1])))))
        a = np.log(np.abs(mus[i])).copy()
        b = np.log(np.abs(mus[i + 1]))
        ka = int(np.argmin(np.abs(a)))
        frac = a[ka] / (a[ka] - b[k]) if a[ka] != b[k] else 0.5
        frac = min(max(frac, 0.0), 1.0)
        out.append({"value": float(values[i] + frac * (values[i + 1] - values[i])),
                    "kind": _crossing_kind(mus[i + 1][k]),
                    "unstable_after": int(n_out[i + 1])})
    return out


def continue_branch(model: str, method: str, parameter: str, start: float, stop: float,
                    fixed: float, *, ds: float = 0.1, ds_min: float = 1e-3, ds_max: float = 0.5,
                    max_points: int = 400, torque_scale: float = 1.0, rtol: float = 1e-9,
                    max_growth: float = 100.0, tol: float = 1e-11,
                    refine: float | None = 1e-4, cadence_rad_s: float | None = None) -> Branch:
    """Follow a branch of periodic orbits from ``start`` to ``stop`` in ``parameter``.

    Secant predictor and pseudo-arclength corrector (Doedel et al. 2003; Keller's method):
    unknowns ``X = (z nodes / z_scale, p)``, equations ``R(z, p) = 0`` and
    ``t . (X - X_pred) = 0`` with ``t`` the unit secant; ``dR/dp`` by a forward difference. The
    step ``ds`` (in the scaled unknowns: m/s or rad/s for the parameter, orbit size for the
    nodes) grows after easy corrections and halves after failures. A fold in the parameter is
    passed (the arclength keeps increasing).

    Parameters
    ----------
    parameter
        ``"speed_m_s"`` (``fixed``: the cadence, rad/s), ``"omega_rad_s"`` (NT only;
        ``fixed``: the speed, m/s) or ``"torque_scale"`` (NT only: the factor on the pedalling
        torques, where folds appear at large torques near the weave resonance; ``fixed``: the
        speed, m/s, and ``cadence_rad_s`` the cadence). Start a torque-scale branch above 0 (the
        orbit of scale 0 is the trivial one, and the unknowns are scaled by the first orbit).
    refine
        Locate each multiplier crossing by bisection to this parameter tolerance (``None``:
        linear interpolation of ``log |mu|`` between branch points only).
    """
    if parameter not in ("speed_m_s", "omega_rad_s", "torque_scale"):
        raise ValueError(f"unknown continuation parameter {parameter!r}")
    if parameter in ("omega_rad_s", "torque_scale") and method != "NT":
        raise ValueError(f"continuation in {parameter} is available for NT (NP has no torques "
                         "and its legs depend on the cadence)")
    if parameter == "torque_scale":
        if cadence_rad_s is None:
            raise ValueError("continuation in torque_scale needs cadence_rad_s")
        if min(start, stop) <= 0.0:
            raise ValueError("a torque-scale branch runs over positive scales "
                             f"(got {start} .. {stop})")
    kw = dict(torque_scale=torque_scale, rtol=rtol, max_growth=max_growth)
    solvers: dict[float, OrbitSolver] = {}

    def solver_at(p: float) -> OrbitSolver:
        if parameter == "speed_m_s":
            s = solvers.get(0.0) or solvers.setdefault(0.0, OrbitSolver(model, method, fixed,
                                                                        **kw))
            s.set_speed(p)
            return s
        if parameter == "torque_scale":
            s = OrbitSolver(model, method, cadence_rad_s, **dict(kw, torque_scale=p))
        else:
            s = OrbitSolver(model, method, p, **kw)
        s.set_speed(fixed)
        return s

    # segments: the worst case over the range, fixed along the branch
    lo, hi = sorted((start, stop))
    probe = np.linspace(lo, hi, 11)
    if parameter == "speed_m_s":
        s0 = solver_at(start)
        m = max(s0.segments_for(p) for p in probe)
    elif parameter == "torque_scale":
        m = solver_at(start).segments_for(fixed)
    else:
        m = max(OrbitSolver(model, method, max(p, 1e-3), **kw).segments_for(fixed)
                for p in probe[:1])

    def first(p: float) -> Orbit:
        s = solver_at(p)
        return s.solve(p if parameter == "speed_m_s" else fixed, segments=m)

    o0 = first(start)
    if not o0.converged:
        raise ConvergenceError(f"no orbit at the branch start {parameter} = {start}",
                               o0.periodicity_residual)
    direction = 1.0 if stop >= start else -1.0
    p1 = start + direction * min(ds, abs(stop - start))
    s = solver_at(p1)
    o1 = s.solve(p1 if parameter == "speed_m_s" else fixed, start=o0.nodes)
    if not o1.converged:
        raise ConvergenceError(f"no orbit at {parameter} = {p1}", o1.periodicity_residual)
    zs = max(float(np.max(np.abs(o0.nodes))), 1e-12)

    def pack(nodes, p):
        return np.concatenate([nodes.ravel() / zs, [p]])

    pts = [(start, o0), (p1, o1)]
    X0, X1 = pack(o0.nodes, start), pack(o1.nodes, p1)
    t = (X1 - X0) / np.linalg.norm(X1 - X0)
    X = X1
    h = ds
    while len(pts) < max_points:
        p_now = X[-1]
        if (p_now - stop) * direction >= 0 or not (min(lo, hi) - 1e-9 <= p_now <= max(lo, hi)
                                                    + 1e-9):
            break
        Xp = X + h * t
        Y = Xp.copy()
        ok, ev = False, None
        for _ in range(8):
            nodes, p = Y[:-1].reshape(m, 4) * zs, float(Y[-1])
            try:
                s = solver_at(p)
                ev = s.residual(nodes)
                R = ev["R"].ravel()
                res = float(np.max(np.abs(R)))
                arc = float(t @ (Y - Xp))
                if res <= tol * zs + 1e-15 and abs(arc) <= 1e-10:
                    ok = True
                    break
                dp = 1e-6 * max(1.0, abs(p))
                ev2 = solver_at(p + dp).residual(nodes, variational=False)
                s = solver_at(p)
            except (FloatingPointError, ZeroDivisionError):
                break
            A = np.zeros((4 * m + 1, 4 * m + 1))
            A[:-1, :-1] = ev["J"] * zs
            A[:-1, -1] = (ev2["R"].ravel() - R) / dp
            A[-1] = t
            try:
                dY = np.linalg.solve(A, -np.concatenate([R, [arc]]))
            except np.linalg.LinAlgError:
                break
            Y = Y + dY
        if not ok:
            h /= 2
            if h < ds_min:
                break
            continue
        orb = s._orbit(nodes, ev, res, True, 0, ev["n_rhs"])
        pts.append((p, orb))
        t_new = (Y - X) / np.linalg.norm(Y - X)
        t = t_new
        X = Y
        h = min(h * 1.5, ds_max)
    values = np.array([p for p, _ in pts])
    orbs = [o for _, o in pts]
    mus = np.array([o.floquet_multipliers for o in orbs])
    crossings = _crossings(values, mus)
    if refine:
        for c in crossings:
            c["value"] = _refine_crossing(solver_at, parameter, fixed, pts, c, refine)
    return Branch(model, method, parameter, float(fixed), values,
                  np.array([o.roll_amplitude_rad for o in orbs]),
                  np.array([o.steer_amplitude_rad for o in orbs]), mus,
                  np.array([o.periodicity_residual for o in orbs]), crossings)


def _refine_crossing(solver_at, parameter, fixed, pts, crossing, tol) -> float:
    """Bisection on the parameter between the two branch points that bracket a crossing
    (where the count of multipliers outside the unit circle changes), to ``tol``."""
    values = [p for p, _ in pts]
    n_out = [int(np.sum(np.abs(o.floquet_multipliers) > 1.0)) for _, o in pts]
    i = next(k for k in range(len(pts) - 1) if n_out[k] != n_out[k + 1]
             and min(values[k], values[k + 1]) <= crossing["value"]
             <= max(values[k], values[k + 1]))
    (a, oa), (b, _) = pts[i], pts[i + 1]
    na = n_out[i]
    while abs(b - a) > tol:
        mid = 0.5 * (a + b)
        s = solver_at(mid)
        o = s.solve(mid if parameter == "speed_m_s" else fixed, start=oa.nodes)
        if not o.converged:
            break
        if int(np.sum(np.abs(o.floquet_multipliers) > 1.0)) == na:
            a, oa = mid, o
        else:
            b = mid
    return 0.5 * (a + b)


# ---------------------------------------------------------------------------------------------
# Command line: pedalrepro periodic
# ---------------------------------------------------------------------------------------------

def add_cli(subparsers) -> None:
    """The ``periodic`` sub-command (:mod:`pedalrepro.cli`)."""
    p = subparsers.add_parser(
        "periodic", help="periodic pedalling response of a non-linear model (shooting)",
        description="Periodic orbit of a non-linear model under pedalling (speed held by a "
                    "rear-hub torque): cadence-harmonic amplitudes and phases, Floquet "
                    "multipliers, periodicity residual. Prints one JSON object.")
    p.add_argument("--model", required=True, help="HS, CF, HR or CR")
    p.add_argument("--speed-m-s", type=float, required=True, dest="speed_m_s",
                   help=f"forward speed, m/s, in [{SPEED_RANGE_M_S[0]}, {SPEED_RANGE_M_S[1]}]")
    p.add_argument("--cadence-rpm", type=float, required=True, dest="cadence_rpm",
                   help=f"cadence, rpm, in [{CADENCE_RANGE_RPM[0]}, {CADENCE_RANGE_RPM[1]}]")
    p.add_argument("--method", default="NT", help="NT (torques, default) or NP (moving legs)")
    p.add_argument("--segments", type=int, default=None,
                   help="shooting segments (1: single shooting; default: from the instability)")
    p.add_argument("--torque-scale", type=float, default=1.0, dest="torque_scale",
                   help="factor on the NT torques (default 1)")
    p.set_defaults(func=_cli)


def _cli(args) -> int:
    import json
    import sys

    if args.segments is not None and not 1 <= args.segments <= 256:
        raise ValueError(f"--segments must be in [1, 256], got {args.segments}")
    try:
        orb = orbit(args.model, args.method, args.speed_m_s,
                    args.cadence_rpm * 2.0 * np.pi / 60.0, segments=args.segments,
                    torque_scale=args.torque_scale)
    except ConvergenceError as exc:
        print(f"pedalrepro periodic: error: {exc}", file=sys.stderr)
        return 3
    print(json.dumps(orb.summary()))
    return 0


# ---------------------------------------------------------------------------------------------
# Workflow outputs (rules/periodic.smk): one function per rule script
# ---------------------------------------------------------------------------------------------

def write_map(path, model: str, method: str, speed_step_m_s: float, speed_max_m_s: float,
              omega_step_rad_s: float, omega_max_rad_s: float, *, rtol: float,
              max_growth: float) -> dict:
    """Orbit map of one model and method on ``0:step:max`` grids, saved as ``.npz``.

    Besides :func:`orbit_map`'s arrays: ``model``, ``method``, ``elapsed_s`` (whole map).
    """
    import time

    v = response.grid(speed_step_m_s, speed_max_m_s)
    w = response.grid(omega_step_rad_s, omega_max_rad_s)
    start = time.perf_counter()
    out = orbit_map(model, method, v, w, rtol=rtol, max_growth=max_growth)
    elapsed = time.perf_counter() - start
    np.savez_compressed(path, model=model, method=method, elapsed_s=elapsed, rtol=rtol, **out)
    out["elapsed_s"] = elapsed
    return out


def write_branches(path, model: str, methods, cadence_rpm: float, speed_range_m_s,
                   torque_scales, *, ds: float, rtol: float, max_growth: float,
                   eigen_step_m_s: float = 0.01) -> list[Branch]:
    """Continuation in speed at one cadence for each method and torque scale, saved as
    ``.npz`` (keys ``<method>_<k>_<field>`` of :meth:`Branch.arrays`, ``torque_scales``,
    ``methods``) with the self-stable speed ranges of the model's own linearisation
    (``linear_stable_ranges_m_s``, n x 2)."""
    w = float(cadence_rpm) * 2.0 * np.pi / 60.0
    lo, hi = (float(x) for x in speed_range_m_s)
    arrays, branches = {}, []
    for method in methods:
        for k, scale in enumerate(torque_scales):
            if method == "NP" and scale != 1.0:
                continue
            br = continue_branch(model, method, "speed_m_s", lo, hi, w, ds=ds, rtol=rtol,
                                 max_growth=max_growth, torque_scale=float(scale))
            branches.append(br)
            arrays.update(br.arrays(f"{method}_{k}_"))
    lin = _Adapter.own_linearisation(model)
    ranges = linear.stable_ranges(lin, np.arange(0.0, hi + 2 * eigen_step_m_s, eigen_step_m_s))
    np.savez_compressed(path, model=model, omega_rad_s=w, cadence_rpm=float(cadence_rpm),
                        methods=np.array(list(methods)),
                        torque_scales=np.asarray(torque_scales, float),
                        linear_stable_ranges_m_s=np.array(ranges, float).reshape(-1, 2),
                        **arrays)
    return branches


def write_tables(map_files, branch_files, time_files, out_maps, out_crossings,
                 out_simulation) -> None:
    """The three tables of ``rules/periodic.smk``: :func:`map_summary`,
    :func:`crossing_table` and :func:`simulation_comparison`, as CSV."""
    maps = [np.load(p) for p in map_files]
    map_summary(maps).to_csv(out_maps, index=False)
    crossing_table([np.load(p) for p in branch_files]).to_csv(out_crossings, index=False)
    simulation_comparison(maps, [np.load(p) for p in time_files]).to_csv(out_simulation,
                                                                         index=False)


def map_summary(maps) -> pd.DataFrame:
    """One row per orbit map: points, converged, stable, residual, multipliers, timing."""
    import pandas as pd

    rows = []
    for d in maps:
        w = np.asarray(d["omega_rad_s"])
        forced = np.broadcast_to(w[None, :] > 0, np.shape(d["converged"]))
        conv = np.asarray(d["converged"]) & forced
        t_ms = 1e3 * np.asarray(d["orbit_time_s"])[forced]
        cpu_ms = 1e3 * np.asarray(d["orbit_cpu_s"])[forced] if "orbit_cpu_s" in d else t_ms
        v = np.asarray(d["speed_m_s"])
        with np.errstate(divide="ignore", invalid="ignore"):
            rd = np.abs(np.asarray(d["roll_amp_rad"]) / np.asarray(d["ps_roll_amp_rad"]) - 1)
        rd = np.where(conv & np.isfinite(rd), 100.0 * rd, -1.0)
        i, j = np.unravel_index(int(np.argmax(rd)), rd.shape)
        rows.append({
            "model": str(d["model"]), "method": str(d["method"]),
            "max_rd_orbit_vs_ps_roll_pct": float(rd[i, j]) if conv.any() else float("nan"),
            "max_rd_at_speed_m_s": float(v[i]), "max_rd_at_omega_rad_s": float(w[j]),
            "median_rd_orbit_vs_ps_roll_pct": float(np.median(rd[conv])) if conv.any()
            else float("nan"),
            "speeds": int(np.size(d["speed_m_s"])), "cadences": int(w.size),
            "orbits": int(forced.sum()), "converged": int(conv.sum()),
            "stable": int((np.asarray(d["stable"]) & forced).sum()),
            "max_residual": float(np.nanmax(np.asarray(d["residual"])[conv])) if conv.any()
            else float("nan"),
            "max_multiplier_abs": float(np.nanmax(np.asarray(d["max_multiplier_abs"])[conv]))
            if conv.any() else float("nan"),
            "max_segments": int(np.max(np.asarray(d["segments"])[forced])) if forced.any()
            else 0,
            "median_ms_per_orbit": float(np.median(t_ms)) if t_ms.size else float("nan"),
            "median_cpu_ms_per_orbit": float(np.median(cpu_ms)) if cpu_ms.size
            else float("nan"),
            "map_s": float(d["elapsed_s"])})
    return pd.DataFrame(rows)


def crossing_table(branch_files) -> pd.DataFrame:
    """Multiplier crossings of the continued branches, beside the nearest stability boundary
    of the model's own linearisation."""
    import pandas as pd

    rows = []
    for b in branch_files:
        bounds = np.asarray(b["linear_stable_ranges_m_s"]).ravel()
        for method in np.atleast_1d(b["methods"]):
            for k, scale in enumerate(np.atleast_1d(b["torque_scales"])):
                key = f"{method}_{k}_crossing_values"
                if key not in b:
                    continue
                for value, kind in zip(b[key], b[f"{method}_{k}_crossing_kinds"], strict=True):
                    near = float(bounds[np.argmin(np.abs(bounds - value))]) if bounds.size \
                        else float("nan")
                    rows.append({"model": str(b["model"]), "method": str(method),
                                 "cadence_rpm": float(b["cadence_rpm"]),
                                 "torque_scale": float(scale), "kind": str(kind),
                                 "speed_m_s": float(value), "linear_boundary_m_s": near,
                                 "shift_m_s": float(value) - near})
    return pd.DataFrame(rows, columns=["model", "method", "cadence_rpm", "torque_scale", "kind",
                                       "speed_m_s", "linear_boundary_m_s", "shift_m_s"])


def simulation_comparison(orbit_maps, time_maps, eigen_step_m_s: float = 0.01) -> pd.DataFrame:
    """Where the simulation-based estimate (thesis NT/NP: DFT of a simulation) agrees with the
    orbit: RD (Eq 3.26, orbit = reference) medians in and outside the self-stable speeds of the
    model's own linearisation, the share of runs that fell, and evaluation point 1a (NT vs NP)
    from orbits and from simulations over the stable region."""
    import pandas as pd

    from . import evaluation

    orbit = {(str(d["model"]), str(d["method"])): d for d in orbit_maps}
    sim = {(str(d["model"]), str(d["method"])): d for d in time_maps}
    rows = []
    for (model, method), o in orbit.items():
        s = sim.get((model, method))
        if s is None:
            continue
        v, w = np.asarray(o["speed_m_s"]), np.asarray(o["omega_rad_s"])
        if not (np.array_equal(v, s["speed_m_s"]) and np.array_equal(w, s["omega_rad_s"])):
            raise ValueError(f"orbit and simulation grids of {model} {method} differ")
        lin = _Adapter.own_linearisation(model)
        ranges = linear.stable_ranges(lin, np.arange(0.0, v.max() + 2 * eigen_step_m_s,
                                                     eigen_step_m_s))
        stable_v = np.zeros(v.shape, bool)
        for lo, hi in ranges:
            stable_v |= (v > lo) & (v < hi)
        forced = w[None, :] > 0
        st = np.broadcast_to(stable_v[:, None], (v.size, w.size)) & forced
        un = ~np.broadcast_to(stable_v[:, None], (v.size, w.size)) & forced
        row = {"model": model, "method": method}
        for dof in ("roll", "steer"):
            rd = evaluation.relative_difference(o[f"{dof}_amp_rad"], s[f"{dof}_amp_rad"])
            for name, mask in (("stable", st), ("unstable", un)):
                vals = rd[mask & np.isfinite(rd)]
                row[f"{dof}_rd_median_{name}_pct"] = float(np.median(vals)) if vals.size \
                    else float("nan")
        row["fell_unstable_pct"] = 100.0 * float(np.mean(np.asarray(s["fell"])[un])) \
            if un.any() else float("nan")
        row["fell_stable_pct"] = 100.0 * float(np.mean(np.asarray(s["fell"])[st])) \
            if st.any() else float("nan")
        rows.append(row)
    out = pd.DataFrame(rows)
    # evaluation point 1a (NT vs NP, NP the reference) from orbits and from simulations
    for model in sorted({m for m, _ in orbit}):
        if not all(k in orbit and k in sim for k in ((model, "NT"), (model, "NP"))):
            continue
        v = np.asarray(orbit[(model, "NT")]["speed_m_s"])
        w = np.asarray(orbit[(model, "NT")]["omega_rad_s"])
        lin = _Adapter.own_linearisation(model)
        stable_v = np.zeros(v.shape, bool)
        for lo, hi in linear.stable_ranges(lin, np.arange(0.0, v.max() + 0.02, 0.01)):
            stable_v |= (v > lo) & (v < hi)
        mask = np.broadcast_to(stable_v[:, None], (v.size, w.size)) & (w[None, :] > 0)
        for src, d in (("orbit", orbit), ("simulation", sim)):
            rd = evaluation.relative_difference(d[(model, "NP")]["roll_amp_rad"],
                                                d[(model, "NT")]["roll_amp_rad"])
            vals = rd[mask & np.isfinite(rd)]
            out.loc[out["model"] == model, f"1a_roll_median_{src}_pct"] = (
                float(np.median(vals)) if vals.size else float("nan"))
        rd = evaluation.relative_difference(orbit[(model, "NP")]["roll_amp_rad"],
                                            orbit[(model, "NT")]["roll_amp_rad"])
        vals = rd[(w[None, :] > 0) & np.isfinite(rd)]
        out.loc[out["model"] == model, "1a_roll_median_orbit_all_speeds_pct"] = (
            float(np.median(vals)) if vals.size else float("nan"))
    return out
