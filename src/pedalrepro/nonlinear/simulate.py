"""Time solutions of a non-linear model under its forcing, through the one fall-event integrator.

:class:`ForcedModel` is a :class:`pedalrepro.integrator.System`: a
:class:`.nonlinear_model.NonlinearModel` with the pedalling torques of Eq 3.14 (harmonics at a
cadence) and/or its prescribed leg motion (``model.spec``). Its right-hand side runs in Python
(``model.rhs``, the reference) or in C (``forced_rhs`` of ``pedalrepro/csrc/model_library.c``:
the null-space right-hand side with the sampled Dormand-Prince loop, :mod:`.library`); the
forcing struct is filled by :func:`.forcing.fill_forcing`. :func:`simulate` is the run of the
NT/NP sweeps (Sec 3.1.2.1): upright straight-ahead start at a speed, sampled on a grid.
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..integrator import CompiledRhs, Simulation, harmonic_torque, integrate
from .forcing import ForcingStruct, fill_forcing
from .nonlinear_model import NonlinearModel

__all__ = ["ForcedModel", "sample_times", "simulate"]


@dataclass
class ForcedModel:
    """A non-linear model with its forcing, ready for :func:`pedalrepro.integrator.integrate`.

    Parameters
    ----------
    model
        The parametrised model (its prescribed legs, if any, in ``model.spec``).
    harmonics, omega_rad_s
        Pedalling torques of Eq 3.14 (``n``, ``roll``, ``steer``) at cadence ``omega_rad_s``
        (none when ``harmonics`` is None or ``omega_rad_s`` is 0).
    torque
        Instead of ``harmonics``, a callable ``torque(t)`` returning the roll and steer torques
        (N m); Python only.

    Notes
    -----
    State ``[roll, pitch, steer, roll rate, rear wheel rate, steer rate]``
    (:mod:`.nonlinear_model`); ``steer_limit_rad`` is the model's (arm reach of CF).
    """

    model: NonlinearModel
    harmonics: object | None = None
    omega_rad_s: float = 0.0
    torque: Callable[[float], tuple[float, float]] | None = None
    roll_index: int = 0
    steer_index: int = 2
    _torque: Callable | None = field(default=None, init=False, repr=False)
    _compiled: CompiledRhs | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        if self.torque is not None and self.harmonics is not None:
            raise ValueError("give harmonics or torque, not both")
        self._torque = self.torque
        if self._torque is None and self.harmonics is not None and self.omega_rad_s > 0:
            self._torque = harmonic_torque(self.harmonics, self.omega_rad_s)

    @property
    def steer_limit_rad(self) -> float:
        return float(self.model.steer_limit_rad)

    def rhs(self, t: float, x: np.ndarray) -> np.ndarray:
        """State derivative (``model.rhs`` with the torques at ``t``)."""
        if self._torque is None:
            return self.model.rhs(t, x)
        return self.model.rhs(t, x, self._torque(t))

    def compiled(self) -> CompiledRhs | None:
        """``forced_rhs`` of the model's library with this forcing, or None (no compiler, or a
        Python ``torque``)."""
        if self._compiled is not None:
            return self._compiled
        lib = self.model.lib
        if lib is None or self.torque is not None:
            return None
        fc = ForcingStruct()
        keep = fill_forcing(fc, self.model, self.harmonics, self.omega_rad_s)
        fn = ctypes.cast(lib.forced_rhs, ctypes.c_void_p).value
        self._compiled = CompiledRhs(lib, fn, fc, keep)
        return self._compiled


def sample_times(duration_s: float, sample_rate_hz: float) -> np.ndarray:
    """``t = 0, 1/fs, ...``: ``round(duration * fs) + 1`` samples."""
    if duration_s <= 0 or sample_rate_hz <= 0:
        raise ValueError("duration_s and sample_rate_hz must be positive")
    return np.arange(int(round(duration_s * sample_rate_hz)) + 1) / sample_rate_hz


def simulate(
    model: NonlinearModel,
    speed_m_s: float,
    duration_s: float,
    sample_rate_hz: float,
    *,
    harmonics=None,
    omega_rad_s: float = 0.0,
    torque: Callable[[float], tuple[float, float]] | None = None,
    x0: np.ndarray | None = None,
    rtol: float = 1e-6,
    atol: float = 1e-8,
    fall_roll_rad: float = 1.0,
    method: str = "RK45",
    compiled: bool = True,
    variant: str = "hermite",
) -> Simulation:
    """Integrate a non-linear model from upright straight-ahead motion.

    Parameters
    ----------
    model
        The model (``rhs``, ``upright_state``).
    speed_m_s
        Initial forward speed (rear wheel rolling), m/s; roll, steer and their rates start at
        zero (Sec 3.1.2.2: zero initial conditions) unless ``x0`` is given.
    duration_s, sample_rate_hz
        Output grid :func:`sample_times`.
    harmonics, omega_rad_s, torque
        The forcing (:class:`ForcedModel`).
    rtol, atol, fall_roll_rad, method, compiled, variant
        As :func:`pedalrepro.integrator.integrate`. The compiled RK45 runs when the model has a
        library and no Python ``torque`` is given; ``variant="hermite"`` is the scheme of the
        NT/NP sweeps.
    """
    t_s = sample_times(duration_s, sample_rate_hz)
    x0 = model.upright_state(speed_m_s) if x0 is None else np.asarray(x0, dtype=float)
    system = ForcedModel(model, harmonics, omega_rad_s, torque)
    return integrate(system, x0, t_s, rtol=rtol, atol=atol, fall_roll_rad=fall_roll_rad,
                     method=method, compiled=compiled, variant=variant)
