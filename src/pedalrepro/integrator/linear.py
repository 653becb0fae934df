"""A linear time-invariant system with harmonic forcing, for :func:`.core.integrate`.

``x' = A x + e_rows Re( sum_k amp_k exp(i w_k t) )``: the linear bicycle models (Eq 3.1) in
first-order form ``x = [roll, steer, roll rate, steer rate]`` with ``A`` the state matrix and the
pedalling torques of Eq 3.14 entering the accelerations as ``M^-1 f(t)``
(:meth:`LinearSystem.bicycle`). Evaluated in Python (``rhs``, the reference) or in C
(``pedalrepro/csrc/linear_rhs.h``, :meth:`LinearSystem.compiled`).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, field

import numpy as np

from .build import linear_library
from .core import CompiledRhs

__all__ = ["LinearSystem"]


class _LinearSystemC(ctypes.Structure):
    _fields_ = [("n", ctypes.c_int), ("a", ctypes.c_void_p), ("n_harm", ctypes.c_int),
                ("w", ctypes.c_void_p), ("amp_re", ctypes.c_void_p),
                ("amp_im", ctypes.c_void_p), ("m", ctypes.c_int), ("rows", ctypes.c_void_p)]


@dataclass
class LinearSystem:
    """``x' = a x + e_rows Re(exp(i w t) @ amp)``.

    Parameters
    ----------
    a
        State matrix (n x n).
    w_rad_s
        Forcing frequencies (k,), rad/s.
    amp
        Complex forcing amplitudes (k, m): harmonic ``k`` on state ``rows[j]``.
    rows
        The states the forcing enters (m,).
    roll_index, steer_index
        Rows of roll and steer in the state (the fall event acts on roll).
    """

    a: np.ndarray
    w_rad_s: np.ndarray
    amp: np.ndarray
    rows: tuple[int, ...]
    roll_index: int = 0
    steer_index: int = 1
    steer_limit_rad: float = float("inf")
    _compiled: CompiledRhs | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        self.a = np.ascontiguousarray(self.a, dtype=float)
        self.w_rad_s = np.ascontiguousarray(self.w_rad_s, dtype=float)
        self.amp = np.ascontiguousarray(self.amp, dtype=complex)
        n = self.a.shape[0]
        if self.a.shape != (n, n) or self.amp.shape != (self.w_rad_s.size, len(self.rows)):
            raise ValueError(f"LinearSystem: a {self.a.shape} must be square and amp "
                             f"{self.amp.shape} (harmonics x forced rows) "
                             f"{(self.w_rad_s.size, len(self.rows))}")
        if not all(0 <= r < n for r in self.rows):
            raise ValueError(f"LinearSystem: forced rows {self.rows} outside 0..{n - 1}")

    @classmethod
    def bicycle(cls, state_matrix: np.ndarray, mass_matrix: np.ndarray, n: np.ndarray,
                coef: np.ndarray, omega_rad_s: float) -> LinearSystem:
        """Eq 3.1 under the pedalling torques of Eq 3.14 at cadence ``omega_rad_s``.

        ``state_matrix`` (4 x 4) of ``[roll, steer, roll rate, steer rate]``; torque
        ``f(t) = Re(sum_k coef[k] (n_k w)^2 exp(i n_k w t))`` with ``coef`` (k, 2) [roll, steer];
        the accelerations gain ``M^-1 f(t)``.
        """
        n = np.asarray(n, dtype=float)
        minv = np.linalg.inv(mass_matrix)
        amp = (minv @ np.asarray(coef).T).T * (n * omega_rad_s)[:, None] ** 2  # (k, 2), M^-1 f
        return cls(state_matrix, n * omega_rad_s, amp, (2, 3))

    def rhs(self, t: float, x: np.ndarray) -> np.ndarray:
        """State derivative at time ``t`` (Python)."""
        acc = np.real(np.exp(1j * self.w_rad_s * t) @ self.amp)
        dx = self.a @ x
        dx[list(self.rows)] += acc
        return dx

    def compiled(self) -> CompiledRhs | None:
        """The same right-hand side in C (``pedalrepro/csrc/linear_rhs.h``), or None without a
        C compiler."""
        if self._compiled is None:
            lib = linear_library()
            if lib is None:
                return None
            rows = np.ascontiguousarray(self.rows, dtype=np.intc)
            re = np.ascontiguousarray(self.amp.real)
            im = np.ascontiguousarray(self.amp.imag)
            ctx = _LinearSystemC(self.a.shape[0], self.a.ctypes.data, self.w_rad_s.size,
                                 self.w_rad_s.ctypes.data, re.ctypes.data, im.ctypes.data,
                                 len(self.rows), rows.ctypes.data)
            fn = ctypes.cast(lib.linear_rhs, ctypes.c_void_p).value
            self._compiled = CompiledRhs(lib, fn, ctx, [self.a, self.w_rad_s, re, im, rows])
        return self._compiled
