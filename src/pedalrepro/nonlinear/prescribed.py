"""Prescribed motion as a Fourier series (the leg and crank motion of method NP)."""

from __future__ import annotations

import numpy as np

__all__ = ["FourierSpec"]


class FourierSpec:
    """Prescribed motion ``s(t)`` as Fourier series: positions, rates, accelerations.

    ``x_i(t) = slope_i t + sum_n Re(coef[i, n] exp(i n omega t))`` (the crank angles turn at
    ``-omega``: ``slope``); rates and accelerations are the exact derivatives of the series.
    """

    def __init__(self, omega_rad_s: float, coef: np.ndarray, slope: np.ndarray) -> None:
        self.omega_rad_s = float(omega_rad_s)
        self.coef = np.ascontiguousarray(coef)
        self.slope = np.ascontiguousarray(slope, dtype=float)
        self._wn = self.omega_rad_s * np.arange(self.coef.shape[1])

    def __call__(self, time_s: float) -> np.ndarray:
        wn = self._wn
        e = np.exp(1j * wn * time_s)
        pos = (self.coef @ e).real + self.slope * time_s
        vel = (self.coef @ (1j * wn * e)).real + self.slope
        acc = (self.coef @ (-(wn**2) * e)).real
        return np.concatenate([pos, vel, acc])

    def harmonic_major(self) -> tuple[np.ndarray, np.ndarray]:
        """Real and imaginary parts of ``coef`` stored harmonic by harmonic (``[n, i]``,
        C-contiguous): the layout of ``four_re``/``four_im`` in
        ``pedalrepro/csrc/forcing.h``, whose loop over the signals then runs on contiguous
        memory."""
        return (np.ascontiguousarray(self.coef.real.T), np.ascontiguousarray(self.coef.imag.T))

    @classmethod
    def from_samples(cls, omega_rad_s: float, signals: np.ndarray, slope: np.ndarray,
                     harmonics: int) -> FourierSpec:
        """Series of ``harmonics`` terms from ``signals`` (rows) sampled evenly over one period
        ``2 pi / omega`` and growing at ``slope`` (rad/s)."""
        samples = signals.shape[1]
        t = 2 * np.pi / omega_rad_s * np.arange(samples) / samples
        periodic = signals - slope[:, None] * t[None, :]
        coef = np.fft.rfft(periodic, axis=1) / samples
        coef[:, 1:] *= 2.0
        return cls(omega_rad_s, coef[:, :harmonics], slope)
