"""Periodic orbits of one model and method: shooting with Newton, Floquet multipliers.

Problem. The forcing has period ``T = 2 pi / omega`` (NT: the harmonic torques of Eq 3.14; NP:
the prescribed leg motion). The reduced state is ``y = [roll, pitch, steer, roll rate, steer
rate]``; the ignorable coordinates (position, yaw, wheel angles) are left out and pitch is a
function of roll and steer (the holonomic ground contact: ``po_pitch`` of
``pedalrepro/csrc/periodic_library.c`` integrates the pitch rate of the velocity constraints
from upright). The orbit's unknowns are the lateral states ``z = [roll, steer, roll rate, steer
rate]``.

Forward speed. In the non-linear model the rear-wheel rate is a free state and the forcing
feeds it (a few 1e-4 m/s per period at 5 m/s), so no exactly periodic motion exists. **Choice:**
the speed is held by a generalised force on the rear-wheel rotation (a hub torque), computed at
every instant so that the rear-wheel acceleration is zero (``model_held_rhs`` of
``pedalrepro/csrc/model_rhs.h``: the simulation's null-space right-hand side with that row
solved for the torque): the constant forward speed that the
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

Continuation and maps: :mod:`.continuation`, :mod:`.maps`.
"""

from __future__ import annotations

import ctypes
import math
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from .. import linear, response
from ..integrator import build
from ..params import LinearModel

__all__ = [
    "DATA_FILES", "SPEED_RANGE_M_S", "CADENCE_RANGE_RPM", "METHODS", "LATERAL",
    "LINEAR_TORQUE_SCALE", "CHORD_PREDICT", "ConvergenceError", "PERIODIC_LIBRARY_C",
    "own_linearisation", "Orbit", "OrbitSolver", "orbit", "small_expm",
]

#: The hand-written sources of the periodic-orbit library besides those of the model's
#: (change tracking).
DATA_FILES: tuple[str, ...] = ("src/pedalrepro/csrc/periodic_library.c",
                               "src/pedalrepro/csrc/dopri_flow.h")
#: Thesis speed range of the maps (Sec 3.1.2.2.1), m/s; the command line accepts this range.
SPEED_RANGE_M_S: tuple[float, float] = (0.0, 10.0)
#: Cadence range accepted by the command line, rpm (the thesis maps reach 4 pi rad/s = 120 rpm).
CADENCE_RANGE_RPM: tuple[float, float] = (1.0, 120.0)
METHODS: tuple[str, ...] = ("NT", "NP")
#: Lateral components of the reduced state y = [roll, pitch, steer, roll rate, steer rate].
LATERAL = (0, 2, 3, 4)
#: Smallest NT torque scale solved directly. Below it (0 included: the upright motion) the orbit
#: is the one at this scale scaled linearly: its amplitude ~1e-8 rad is still resolved by the
#: integration (absolute tolerances rtol x amplitude ~1e-17), and its non-linear terms are
#: O(scale^2) ~ 1e-12 relative. Smaller orbits are not: at 1e-300 the states no longer control
#: the step size, the variational equations go unresolved and HR at 5 m/s came out unstable
#: (largest multiplier modulus 16.3). Floquet multipliers are those of that orbit, equal to the
#: upright motion's exp(lambda T) of the linearisation to ~1e-8
#: (tests/periodic/test_periodic_inputs.py).
LINEAR_TORQUE_SCALE = 1e-6
#: The chord steps stop once the next iterate is predicted (observed contraction times the
#: residual) within this factor of the convergence goal (:meth:`OrbitSolver._chord_start`).
CHORD_PREDICT = 0.3


class ConvergenceError(RuntimeError):
    """Newton did not converge; ``residual`` is the smallest periodicity residual reached."""

    def __init__(self, message: str, residual: float) -> None:
        super().__init__(message)
        self.residual = residual


# ---------------------------------------------------------------------------------------------
# Adapter: the only place that touches pedalrepro.nonlinear (models, linearisation, generated C)
# ---------------------------------------------------------------------------------------------

#: Entry file of the periodic-orbit library (in :data:`pedalrepro.integrator.build.CSRC`).
PERIODIC_LIBRARY_C = "periodic_library.c"


class _Adapter:
    """Models, their own linearisation and the compiled periodic driver of a model variant."""

    @staticmethod
    def models() -> tuple[str, ...]:
        """The four models of the thesis; each has a non-linear counterpart."""
        from ..params import MODELS

        return tuple(MODELS)

    @staticmethod
    @cache
    def nt_model(name: str):
        from ..nonlinear import sweep

        return sweep.nt_model(name)

    @staticmethod
    def np_model(name: str, omega_rad_s: float):
        from ..nonlinear import sweep

        return sweep.np_model(name, omega_rad_s)

    @staticmethod
    @cache
    def own_linearisation(name: str) -> LinearModel:
        """Eq 3.1 matrices of the NT model linearised about upright motion (complex step)."""
        from ..nonlinear import nonlinear_model

        nl = _Adapter.nt_model(name)
        mats = nonlinear_model.benchmark_matrices(nl)
        return LinearModel(f"{name} (own linearisation)", mats["M"], mats["C1"], mats["K0"],
                           mats["K2"], float(nl.bench["g"]))

    @staticmethod
    def generated_c(nl) -> Path:
        """The model's generated ``constraint_matrix`` and ``dynamics`` (C file)."""
        from ..nonlinear import codegen

        return Path(codegen.generated_c(nl.options))

    @staticmethod
    @cache
    def forcing_struct() -> type[ctypes.Structure]:
        """``po_forcing`` of :file:`periodic_library.c`: the forcing ``forcing_t``
        (:class:`pedalrepro.nonlinear.forcing.ForcingStruct`, filled by its one builder)
        followed by the periodic driver's own fields."""
        from ..nonlinear.forcing import ForcingStruct

        class Forcing(ctypes.Structure):
            _fields_ = [("f", ForcingStruct), ("u_rear", ctypes.c_double),
                        ("omega_q", ctypes.c_double), ("fd_step", ctypes.c_double),
                        ("central", ctypes.c_int), ("nvar", ctypes.c_int)]

        return Forcing

    @staticmethod
    @cache
    def library(model_c: Path) -> ctypes.CDLL:
        """:file:`periodic_library.c` with the model's code, compiled once into the model cache
        folder."""
        from ..nonlinear import codegen

        so = build.build(PERIODIC_LIBRARY_C, Path(codegen.cache_dir()), "periodic",
                         model_c=model_c)
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

    @staticmethod
    def fill_forcing(fc, nl, harmonics, omega_rad_s: float) -> list:
        """The forcing of ``nl`` into ``fc`` (:func:`pedalrepro.nonlinear.forcing.fill_forcing`)."""
        from ..nonlinear.forcing import fill_forcing

        return fill_forcing(fc, nl, harmonics, omega_rad_s)


def own_linearisation(model: str) -> LinearModel:
    """Eq 3.1 matrices of ``model``'s NT model linearised about upright motion (complex step;
    cached): the linear reference of the orbits (PS start, stability boundaries)."""
    return _Adapter.own_linearisation(model)


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
    #: Jacobian of the shooting equations (4m x 4m) at the iterate whose variational equations
    #: were integrated (empty when none was): a neighbour's chord start (:meth:`OrbitSolver.solve`).
    jacobian: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((0, 0)))

    @property
    def stable(self) -> bool:
        """All Floquet multipliers inside the unit circle."""
        return bool(np.max(np.abs(self.floquet_multipliers)) < 1.0)

    def summary(self) -> dict:
        """JSON-ready summary (the ``pedalrepro periodic`` output)."""
        out = {k: v for k, v in asdict(self).items() if k not in (
            "nodes", "monodromy", "jacobian", "floquet_multipliers", "failure")}
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
        Factor on the NT torques (1e-3: the linear limit), finite; NP accepts only 1. Below
        :data:`LINEAR_TORQUE_SCALE` in magnitude (0: the upright motion) the orbit is the one
        at that scale scaled linearly (:meth:`solve`).
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
        if not math.isfinite(torque_scale):
            raise ValueError(f"torque_scale must be finite, got {torque_scale}")
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
        fc = _Adapter.forcing_struct()()
        self._keep = _Adapter.fill_forcing(fc.f, self.nl,
                                           self.harmonics if method == "NT" else None,
                                           self.omega_rad_s)
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
        self._memo_jac: dict = {}
        self._memo_ps: dict = {}
        #: Observed contraction of the first chord step of the last orbit solved with two
        #: guides, per segment count (:meth:`_chord_start`).
        self._first_rate: dict[int, float] = {}
        self._linear_proxy: OrbitSolver | None = None
        if method == "NT" and abs(self.torque_scale) < LINEAR_TORQUE_SCALE:
            self._linear_proxy = OrbitSolver(
                model, method, omega_rad_s, torque_scale=LINEAR_TORQUE_SCALE,
                harmonics=harmonics, rtol=rtol, max_growth=max_growth, fd_step=fd_step,
                central=central, half_period=half_period)

    @property
    def shoot_s(self) -> float:
        """Length of the shooting interval: half the period with the odd symmetry, else T."""
        return self.period_s / 2 if self.half_period else self.period_s

    # -- low level ----------------------------------------------------------------------------
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
            out["J"], out["H"] = _shooting_jacobian(G)
        return out

    def linear_jacobian(self, speed_m_s: float, m: int) -> np.ndarray:
        """Jacobian of the shooting equations on ``m`` segments for the upright motion of the
        model's own linearisation: every segment's ``G`` is ``expm(A(v) T_s / m)`` (the last one
        with the half-period sign). The orbit's Jacobian differs from it by the non-linear terms
        (relative O(amplitude^2) for NT; for NP also the legs' periodic inertia), so chord steps
        with it contract the residual by about that factor per step (:meth:`solve`). Kept for
        the last few speeds (a map's orbit asks for its own and its two guides'), read-only."""
        def make() -> np.ndarray:
            g = small_expm(linear.state_matrix(self.linear, speed_m_s) * (self.shoot_s / m))
            sign = -1.0 if self.half_period else 1.0
            return _shooting_jacobian([g] * (m - 1) + [sign * g])[0]

        return _memoised(self._memo_jac, (float(speed_m_s), int(m)), make)

    def chord_jacobian(self, speed_m_s: float, m: int, guide: Orbit | None = None,
                       second: Orbit | None = None) -> np.ndarray:
        """Jacobian of the chord steps of :meth:`solve` on ``m`` segments: that of the model's
        own linearisation (:meth:`linear_jacobian`), plus, with a converged ``guide`` orbit
        on ``m`` segments at another speed (a map's or a branch's neighbour), the non-linear
        part of the guide's Jacobian, ``J_guide - linear_jacobian(v_guide)``. The linear part
        follows the speed exactly; the non-linear part (for NP mostly the legs' periodic inertia,
        which the linearisation leaves out) changes little between neighbouring speeds, so the
        chord steps contract the residual by far more than with the linear part alone. With a
        ``second`` guide that part is extrapolated linearly in speed from the two."""
        jac = self.linear_jacobian(speed_m_s, m)
        if self._guides(guide, m):
            dev = guide.jacobian - self.linear_jacobian(guide.speed_m_s, m)
            if self._guides(second, m) and second.speed_m_s != guide.speed_m_s:
                dev2 = second.jacobian - self.linear_jacobian(second.speed_m_s, m)
                dev = dev + (dev - dev2) * ((speed_m_s - guide.speed_m_s)
                                            / (guide.speed_m_s - second.speed_m_s))
            jac = jac + dev
        return jac

    def start_nodes(self, speed_m_s: float, m: int, guide: Orbit | None = None,
                    second: Orbit | None = None) -> np.ndarray:
        """Newton's start on ``m`` segments: the PS nodes (:meth:`ps_state`), plus, with a
        converged ``guide`` orbit at another speed, the guide's departure from its own PS
        (the non-linear part of the orbit), extrapolated linearly in speed with a ``second``
        guide (:meth:`chord_jacobian` does the same with the Jacobians)."""
        nodes = self._ps_nodes(speed_m_s, m)
        if not self._guides(guide, m):
            return nodes.copy()
        dep = guide.nodes - self._ps_nodes(guide.speed_m_s, m)
        if self._guides(second, m) and second.speed_m_s != guide.speed_m_s:
            dep2 = second.nodes - self._ps_nodes(second.speed_m_s, m)
            dep = dep + (dep - dep2) * ((speed_m_s - guide.speed_m_s)
                                        / (guide.speed_m_s - second.speed_m_s))
        return nodes + dep

    def _ps_nodes(self, speed_m_s: float, m: int) -> np.ndarray:
        """PS at the ``m`` node times (:meth:`ps_state`), kept for the last few speeds."""
        return _memoised(self._memo_ps, (float(speed_m_s), int(m)),
                         lambda: self.ps_state(speed_m_s, self.node_times(m)[:-1]))

    def _guides(self, guide: Orbit | None, m: int) -> bool:
        """Whether ``guide`` is a converged orbit of this problem (model, method, cadence,
        torque scale, half period) on ``m`` segments, with its Jacobian."""
        return (guide is not None and guide.converged and guide.segments == m
                and guide.jacobian.shape == (4 * m, 4 * m) and guide.model == self.model
                and guide.method == self.method and guide.omega_rad_s == self.omega_rad_s
                and guide.torque_scale == self.torque_scale
                and guide.half_period == self.half_period)

    def _chord_start(self, nodes: np.ndarray, atol: np.ndarray, goal: float,
                     max_steps: int = 6, guide: Orbit | None = None,
                     second: Orbit | None = None) -> tuple[np.ndarray, int, int, float]:
        """Chord steps with :meth:`linear_jacobian` from ``nodes``, integrating the state only
        (a fifth of the cost of an evaluation with the variational equations), until the next
        iterate is predicted to meet ``goal`` (the absolute residual of convergence) from the
        observed contraction, or the contraction is poor (then the best iterate so far).
        Returns the nodes at which Newton with the variational equations continues, the chord
        evaluations, their right-hand-side count and, when the steps stopped on the prediction
        after the first step, the residual before that step (else NaN). The variational
        equations (Jacobian, monodromy, Floquet multipliers) are then integrated at an iterate
        that is already on the orbit to about ``goal`` instead of at the particular-solution
        start.

        The first step's contraction is not yet observed when it is taken: it is taken as that
        observed on the last orbit solved with two guides on as many segments (a map's
        neighbour at the next lower speed: the contraction of the first step varies little
        between neighbours, 1e-6 to 1e-4 on the finer NT grid), else as 1e-2. Where that
        predicts convergence the evaluation after the first step is Newton's with the
        variational equations, one state-only evaluation fewer (about a sixth of an orbit)."""
        m = nodes.shape[0]
        try:
            inv = np.linalg.inv(self.chord_jacobian(self.speed_m_s, m, guide, second))
        except np.linalg.LinAlgError:
            return nodes, 0, 0, math.nan
        two = self._guides(guide, m) and self._guides(second, m)
        first_rate = self._first_rate.get(m, 1e-2) if two else 1e-2
        best, prev, total, k = nodes, np.inf, 0, 0
        for k in range(1, max_steps + 1):
            try:
                ev = self.residual(nodes, variational=False, atol=atol)
            except (FloatingPointError, ZeroDivisionError):
                return best, k, total, math.nan
            total += ev["n_rhs"]
            res = float(np.max(np.abs(ev["R"])))
            if not np.isfinite(res) or res > 0.3 * prev:
                return best, k, total, math.nan  # poor contraction: Newton from the best iterate
            if k == 2 and two:
                self._first_rate[m] = res / prev
            best = nodes
            if res <= goal:
                return nodes, k, total, math.nan
            rate = res / prev if np.isfinite(prev) else first_rate
            nodes = nodes - (inv @ ev["R"].ravel()).reshape(m, 4)
            prev = res
            if rate * res <= CHORD_PREDICT * goal:
                return nodes, k, total, (res if k == 1 and two else math.nan)
        return nodes, k, total, math.nan

    def solve(self, speed_m_s: float, start: np.ndarray | None = None, *,
              segments: int | None = None, max_iter: int = 12, tol: float = 1e-10,
              switch: float = 1e-6, chord_start: bool = True,
              guide: Orbit | None = None, second: Orbit | None = None) -> Orbit:
        """Periodic orbit at ``speed_m_s`` by Newton from ``start`` (nodes) or the PS.

        ``segments``: 1 for single shooting; default :meth:`segments_for`. ``tol``: relative
        convergence tolerance on the max-norm residual (scaled by the orbit's size). The
        variational equations (Jacobian and monodromy) are integrated while the relative
        residual exceeds ``switch``; closer to the orbit the last Jacobian is reused (chord
        steps), so the Floquet multipliers belong to an iterate within ``switch`` of the orbit.
        With ``chord_start`` (default) Newton is preceded by chord steps with the Jacobian of
        the model's own linearisation (:meth:`_chord_start`, state only): the first evaluation
        with the variational equations is then usually already on the orbit (converged), one
        instead of two or three such evaluations per orbit (a variational evaluation costs
        about four state-only ones), and the multipliers belong to the converged iterate.
        ``iterations`` counts the chord evaluations too. ``guide`` (and ``second``): converged
        orbits of this solver at other speeds (a map's neighbours at the next lower speeds),
        used only where they have the same segments: the start is the PS corrected by their
        departure from their own PS (:meth:`start_nodes`) and the chord steps use the linear
        Jacobian corrected by the non-linear part of theirs (:meth:`chord_jacobian`), so that
        fewer chord steps are needed (NP: about 5 instead of 7 per orbit); the orbit is the same
        to Newton's tolerance (tests/periodic/test_periodic_speed.py). Returns an
        :class:`Orbit` with ``converged`` False when Newton fails (never raises for that). A
        torque scale below :data:`LINEAR_TORQUE_SCALE` (0 included) gives the orbit at that
        scale scaled linearly (amplitudes, nodes, residual and peaks by the ratio of the
        scales, the mean holding torque by its square, phases and multipliers unchanged; at
        scale 0 the amplitudes are 0 and the phases those of the limit).
        """
        self.set_speed(speed_m_s)
        if self._linear_proxy is not None:
            return self._scaled(self._linear_proxy.solve(speed_m_s, segments=segments,
                                                         max_iter=max_iter, tol=tol,
                                                         switch=switch,
                                                         chord_start=chord_start))
        if start is not None:
            nodes = np.array(start, float).reshape(-1, 4)
            m = nodes.shape[0]
        else:
            m = segments or self.segments_for(speed_m_s)
            nodes = self.start_nodes(speed_m_s, m, guide, second)
        scale = max(float(np.max(np.abs(nodes))), 1e-300)
        atol = self.rtol * np.array([scale, 1.0, scale, scale, scale])
        chord, total, before = 0, 0, math.nan
        if chord_start:
            nodes, chord, total, before = self._chord_start(nodes, atol, tol * scale,
                                                            guide=guide, second=second)
        best_res, best_nodes, best_ev = np.inf, nodes, None
        jac = None
        it, ok, prev_res, why = 0, False, np.inf, ""
        for it in range(max_iter + 1):
            # after a first evaluation that the neighbour's contraction predicted converged but
            # was not, the variational equations once more at the Newton iterate, so that the
            # multipliers belong to an iterate on the orbit as without the prediction
            need = jac is None or best_res > switch * scale or (it == 1 and before > 0)
            try:
                ev = self.residual(nodes, variational=need, atol=atol)
            except (FloatingPointError, ZeroDivisionError) as exc:
                why = str(exc)
                break
            total += ev["n_rhs"]
            if need:
                jac = ev
            res = float(np.max(np.abs(ev["R"])))
            if it == 0 and before > 0 and np.isfinite(res):
                self._first_rate[m] = res / before  # the first chord step's contraction
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
            out = self._failed(best_nodes, m, it + chord, total)
        else:
            out = self._orbit(best_nodes, dict(best_ev, H=jac["H"], J=jac["J"]), best_res,
                              ok and best_res <= 1e-9, it + chord, total)
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
                     float(ev["quad"][4] / self.shoot_s), total, ev["H"], jacobian=ev["J"])

    def _scaled(self, ref: Orbit) -> Orbit:
        """The orbit ``ref`` of the linear proxy scaled to this solver's torque scale."""
        ratio = self.torque_scale / LINEAR_TORQUE_SCALE
        flip = np.pi if ratio < 0 else 0.0
        return Orbit(self.model, self.method, ref.speed_m_s, self.omega_rad_s, self.torque_scale,
                     ref.nodes * ratio, ref.roll_amplitude_rad * abs(ratio),
                     ref.steer_amplitude_rad * abs(ratio),
                     float(np.angle(np.exp(1j * (ref.roll_phase_rad + flip)))),
                     float(np.angle(np.exp(1j * (ref.steer_phase_rad + flip)))),
                     ref.floquet_multipliers, ref.periodicity_residual * abs(ratio),
                     ref.converged, ref.iterations, ref.segments, ref.half_period,
                     ref.peak_roll_rad * abs(ratio), ref.peak_steer_rad * abs(ratio),
                     ref.hold_torque_mean_nm * ratio**2, ref.n_rhs, ref.monodromy, ref.failure)

    def _failed(self, nodes, m, it, total) -> Orbit:
        nan = float("nan")
        return Orbit(self.model, self.method, self.speed_m_s, self.omega_rad_s, self.torque_scale,
                     nodes, nan, nan, nan, nan, np.full(4, nan + 0j), float("inf"), False, it, m,
                     self.half_period, nan, nan, nan, total)


def _memoised(memo: dict, key, make, size: int = 8) -> np.ndarray:
    """``memo[key]``, made read-only by ``make()`` when missing; the oldest entries beyond
    ``size`` are dropped."""
    if key not in memo:
        value = make()
        value.setflags(write=False)
        memo[key] = value
        while len(memo) > size:
            memo.pop(next(iter(memo)))
    return memo[key]


def small_expm(a: np.ndarray) -> np.ndarray:
    """Matrix exponential of a small matrix by scaling and squaring of its Taylor series (18
    terms at norm <= 1/2: truncation below 1e-20 relative; scipy's expm took 6 ms per 4 x 4
    here, more than the chord evaluation it serves)."""
    s = max(0, int(np.ceil(np.log2(max(np.linalg.norm(a, 1), 1e-300) / 0.5))))
    b = a / 2.0**s
    out, term = np.eye(a.shape[0]), np.eye(a.shape[0])
    for k in range(1, 19):
        term = term @ b / k
        out = out + term
    for _ in range(s):
        out = out @ out
    return out


def _shooting_jacobian(G: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Jacobian of the shooting equations ``z_{k+1}(z_k) - z_{k+1} = 0`` (the last one closing
    on the first node) from the segments' ``G_k = dz_{k+1}/dz_k``, and their product (the
    monodromy matrix of the shooting interval)."""
    m = len(G)
    J = np.zeros((4 * m, 4 * m))
    H = np.eye(4)
    for k in range(m):
        J[4 * k:4 * k + 4, 4 * k:4 * k + 4] += G[k]
        nxt = 0 if k == m - 1 else k + 1
        J[4 * k:4 * k + 4, 4 * nxt:4 * nxt + 4] -= np.eye(4)
        H = G[k] @ H
    return J, H


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


