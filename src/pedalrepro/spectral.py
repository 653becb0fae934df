"""Hann-windowed discrete Fourier analysis of time solutions (Sec 3.1.2.1.1, Eq 3.2-3.7).

Single-sided amplitudes: ``x(t) = X0 + sum_k |X_k| cos(2 pi f_k t + angle X_k)`` (Eq 3.5), i.e.
``|X_k| = 2 |DFT_k| / N`` for ``k > 0``. With a window ``H`` the amplitudes are multiplied by the
correction ``A_H = N / sum(H)`` (Sec 3.1.2.1.1), so a windowed amplitude is
``2 |DFT(x H)_k| / sum(H)``. The Hann window is the symmetric one of Matlab's ``hann(N)``
(``scipy.signal.windows.hann(N, sym=True)``), which the thesis used; :func:`window` computes it
with scipy's own operations in numpy (bit-identical, tested) so that a sweep job does not import
``scipy.signal`` (0.9 s of its start-up).
"""

from __future__ import annotations

import numpy as np

__all__ = ["WINDOWS", "window", "spectrum", "coefficient_at", "amplitude_at"]

WINDOWS: tuple[str | None, ...] = ("hann", None)


def window(n: int, kind: str | None = "hann") -> np.ndarray:
    """The window ``H(n)`` of length ``n``: ``"hann"`` (symmetric) or ``None`` (rectangular)."""
    if n < 2:
        raise ValueError(f"a spectrum needs at least 2 samples, got {n}")
    if kind is None:
        return np.ones(n)
    if kind == "hann":  # scipy.signal.windows.general_cosine(n, [0.5, 0.5], sym=True)
        fac = np.linspace(-np.pi, np.pi, n)
        w = np.zeros(n)
        for k, a in enumerate((0.5, 0.5)):
            w += a * np.cos(k * fac)
        return w
    raise ValueError(f"unknown window {kind!r}: expected one of {WINDOWS}")


def _clean(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    if x.ndim == 0:
        raise ValueError("x must be a time series (at least 1-D)")
    if not np.all(np.isfinite(x)):
        raise ValueError("x contains NaN or inf: trim the series at the fall event first")
    return x


def spectrum(
    x: np.ndarray, sample_rate_hz: float, window: str | None = "hann"
) -> tuple[np.ndarray, np.ndarray]:
    """Single-sided amplitude spectrum with the amplitude correction ``N / sum(H)``.

    Parameters
    ----------
    x
        Samples along the last axis (any leading shape).
    sample_rate_hz
        Sampling frequency ``f_s`` (Hz).
    window
        ``"hann"`` or ``None``.

    Returns
    -------
    frequency_hz, amplitude
        ``f_k = k f_s / N`` (Eq 3.7) for ``k = 0 .. N//2``, and the amplitudes (same unit as x).
    """
    x = _clean(x)
    n = x.shape[-1]
    h = globals()["window"](n, window)
    dft = np.fft.rfft(x * h, axis=-1)
    amp = 2.0 * np.abs(dft) / h.sum()
    amp[..., 0] /= 2.0
    if n % 2 == 0:
        amp[..., -1] /= 2.0
    return np.fft.rfftfreq(n, 1.0 / sample_rate_hz), amp


def coefficient_at(
    x: np.ndarray, sample_rate_hz: float, frequency_hz: float | np.ndarray,
    window: str | None = "hann",
) -> np.ndarray:
    """Complex single-sided Fourier coefficient of ``x`` at exactly ``frequency_hz``.

    The DFT sum of Eq 3.2 evaluated at the given frequency (not the nearest bin), with the window
    and its amplitude correction: ``2 sum_n x(n) H(n) exp(-i 2 pi f n / f_s) / sum(H)``. For a
    record holding a whole number of periods this equals the DFT bin.

    Parameters
    ----------
    x
        Samples along the last axis, leading shape ``S``.
    frequency_hz
        Scalar or array broadcasting against ``S``.
    """
    x = _clean(x)
    n = x.shape[-1]
    h = globals()["window"](n, window)
    f = np.asarray(frequency_hz, dtype=float)[..., None]
    k = np.arange(n)
    kernel = h * np.exp(-2j * np.pi * f * k / sample_rate_hz)
    return 2.0 * np.sum(x * kernel, axis=-1) / h.sum()


def amplitude_at(
    x: np.ndarray, sample_rate_hz: float, frequency_hz: float, window: str | None = "hann"
) -> float | np.ndarray:
    """Amplitude of ``x`` at the cadence frequency (Sec 3.1.2.1.1; the thesis's "FFT" method).

    Parameters
    ----------
    x
        Time series (1-D, or samples along the last axis).
    sample_rate_hz
        Sampling frequency (Hz).
    frequency_hz
        The frequency to read (Hz), e.g. ``cadence_rad_s / (2 pi)``.
    window
        ``"hann"`` (default, with ``N / sum(H)`` correction) or ``None``.

    Returns
    -------
    float or numpy.ndarray
        A float for a 1-D series, else an array of the leading shape.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(0, 60, 0.01)
    >>> round(amplitude_at(0.02 * np.cos(2 * np.pi * 1.0 * t + 0.3), 100.0, 1.0), 6)
    0.02
    """
    a = np.abs(coefficient_at(x, sample_rate_hz, frequency_hz, window))
    return float(a) if np.ndim(a) == 0 else a
