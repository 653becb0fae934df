"""Cadence and cadence-frequency amplitudes of a run (Sec 4.1, Sec 3.1.2.1.1).

The thesis reads the cadence from the spectral peak of the right-foot marker; a 60 s record at
100 Hz has a bin width of 1/60 Hz = 1 rpm, which is why Table 4.1 lists whole rpm. Here the peak
of the Hann-windowed spectrum (:func:`pedalrepro.spectral.spectrum`) is refined by Gaussian
(log-parabolic) interpolation of the three bins around it, which puts the estimate within a few
hundredths of a bin; the whole-bin value is kept as ``cadence_bin_rpm``. The slope of the
unwrapped crank angle gives an independent check.

Amplitudes at the cadence use the Hann-windowed DFT with the ``N / sum(H)`` correction
(:func:`pedalrepro.spectral.amplitude_at`, the thesis's "FFT" method) evaluated at the detected
cadence frequency.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import spectral
from .kinematics import Kinematics, fill_gaps
from .reader import Run

__all__ = [
    "CADENCE_BAND_HZ", "Cadence", "foot_signal", "peak_frequency_hz", "detect_cadence",
    "amplitudes_at_cadence", "amplitudes_nearest_bin", "scalloping_factor",
]

#: Band searched for the pedalling peak (Hz): 6-180 rpm.
CADENCE_BAND_HZ: tuple[float, float] = (0.1, 3.0)


@dataclass(frozen=True)
class Cadence:
    """Detected cadence of a run.

    Attributes
    ----------
    cadence_rpm
        Interpolated spectral peak of the right-foot marker (rpm).
    cadence_bin_rpm
        The whole-bin peak (the thesis's resolution: 1 rpm for 60 s).
    cadence_crank_rpm
        Mean rate of the unwrapped crank angle (independent check).
    """

    cadence_rpm: float
    cadence_bin_rpm: float
    cadence_crank_rpm: float

    @property
    def cadence_hz(self) -> float:
        return self.cadence_rpm / 60.0

    @property
    def cadence_rad_s(self) -> float:
        return self.cadence_rpm * 2.0 * np.pi / 60.0


def foot_signal(run: Run, kin: Kinematics) -> np.ndarray:
    """Forward position of the right-foot marker (1) relative to the rear-wheel centre, along
    the heading ``b1`` (m): periodic at the cadence, free of the bicycle's drift on the belt."""
    foot = np.where(np.isfinite(run.marker(1, raw=True)), run.marker(1, raw=True),
                    run.marker(1))
    wheel = 0.5 * (run.marker(25) + run.marker(31))
    heading = np.stack([np.cos(kin.yaw_rad), np.sin(kin.yaw_rad)], axis=1)
    x = np.sum((foot - wheel)[:, :2] * heading, axis=1)
    if np.isfinite(x).sum() < 0.5 * x.size:
        raise ValueError(f"run {run.run_id}: the right-foot marker (1) is missing in more than "
                         "half the run: no cadence")
    return fill_gaps(run.t_s, x)


def peak_frequency_hz(x: np.ndarray, sample_rate_hz: float,
                      band_hz: tuple[float, float] = CADENCE_BAND_HZ) -> tuple[float, float]:
    """Spectral peak of ``x`` in ``band_hz``: (interpolated, whole-bin) frequency in Hz.

    Gaussian interpolation over the peak bin and its neighbours of the Hann spectrum:
    ``k* = k + (ln a[k-1] - ln a[k+1]) / (2 (ln a[k-1] - 2 ln a[k] + ln a[k+1]))``.
    """
    f, a = spectral.spectrum(np.asarray(x, float) - np.mean(x), sample_rate_hz, "hann")
    inband = np.flatnonzero((f >= band_hz[0]) & (f <= band_hz[1]))
    if inband.size < 3:
        raise ValueError("record too short to resolve the cadence band")
    k = int(inband[np.argmax(a[inband])])
    if k <= 0 or k >= a.size - 1:
        return float(f[k]), float(f[k])
    la, lb, lc = np.log(np.maximum(a[k - 1:k + 2], 1e-300))
    den = la - 2 * lb + lc
    shift = 0.5 * (la - lc) / den if den < 0 else 0.0
    df = f[1] - f[0]
    return float(f[k] + shift * df), float(f[k])


def detect_cadence(run: Run, kin: Kinematics) -> Cadence:
    """Cadence of a run from the right-foot marker's spectrum, checked by the crank angle."""
    fs = run.sample_rate_hz
    f_peak, f_bin = peak_frequency_hz(foot_signal(run, kin), fs)
    slope = np.polyfit(kin.t_s, kin.crank_rad, 1)[0]  # rad/s, negative while pedalling
    return Cadence(cadence_rpm=60.0 * f_peak, cadence_bin_rpm=60.0 * f_bin,
                   cadence_crank_rpm=float(-slope * 60.0 / (2.0 * np.pi)))


def amplitudes_at_cadence(kin: Kinematics, cadence: Cadence, sample_rate_hz: float,
                          harmonic: int = 1) -> dict[str, float]:
    """Roll, steer and yaw amplitudes (rad) at ``harmonic`` x cadence (Hann DFT, Sec 3.1.2.1.1).

    The mean is removed first; the amplitude is read at the detected frequency (not the nearest
    bin), :func:`pedalrepro.spectral.amplitude_at`.
    """
    f = harmonic * cadence.cadence_hz
    out = {}
    for name in ("roll", "steer", "yaw"):
        x = getattr(kin, f"{name}_rad")
        out[f"{name}_amp_rad"] = float(spectral.amplitude_at(x - x.mean(), sample_rate_hz, f))
    return out


def amplitudes_nearest_bin(kin: Kinematics, cadence: Cadence, sample_rate_hz: float
                           ) -> dict[str, float]:
    """The thesis's amplitudes for measurements (Sec 3.1.2.1.1, Sec 4.1): the Hann-windowed DFT
    bin nearest the cadence, the cadence being the right foot's whole-bin spectral peak
    (``cadence_bin_rpm``; bins are ``1 / T`` apart, 1 rpm for 60 s).

    Unlike :func:`amplitudes_at_cadence` (the DFT evaluated at the exact cadence), this
    includes the Hann window's scalloping loss: a cadence ``d`` bins off the bin reads
    ``sinc(d) / (1 - d^2)`` of the amplitude (down to 0.85 at half a bin).
    """
    out = {}
    for name in ("roll", "steer", "yaw"):
        x = getattr(kin, f"{name}_rad")
        f, a = spectral.spectrum(x - x.mean(), sample_rate_hz, "hann")
        k = int(np.argmin(np.abs(f - cadence.cadence_bin_rpm / 60.0)))
        out[f"{name}_amp_rad"] = float(a[k])
    return out


def scalloping_factor(offset_bins: float) -> float:
    """Hann window amplitude response ``sinc(d) / (1 - d^2)`` at ``d`` bins off a bin
    (continuous-window approximation, exact as N -> infinity; Brandt 2011)."""
    d = float(offset_bins)
    if abs(abs(d) - 1.0) < 1e-12:
        return 0.5
    return float(np.sinc(d) / (1.0 - d * d))
