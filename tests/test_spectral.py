"""Hann-windowed DFT amplitudes (Sec 3.1.2.1.1)."""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import spectral


def test_amplitude_of_a_pure_cosine_whole_periods():
    fs = 100.0
    t = np.arange(0, 60, 1 / fs)
    x = 0.3 + 0.02 * np.cos(2 * np.pi * 1.0 * t + 0.4)
    assert spectral.amplitude_at(x, fs, 1.0, window=None) == pytest.approx(0.02, rel=1e-12)
    assert spectral.amplitude_at(x, fs, 1.0) == pytest.approx(0.02, rel=2e-4)
    f, a = spectral.spectrum(x, fs, window=None)
    assert a[0] == pytest.approx(0.3, rel=1e-12)
    assert a[np.argmin(np.abs(f - 1.0))] == pytest.approx(0.02, rel=1e-12)


def test_hann_reduces_leakage_off_bin():
    """Sec 3.1.2.1.1: off-bin frequencies lose up to 36 % without a window, ~15 % with Hann."""
    fs = 50.0
    t = np.arange(0, 10.0, 1 / fs)  # 10 s: a 1.05 Hz tone (10.5 periods) sits between bins
    x = np.cos(2 * np.pi * 1.05 * t)
    f, rect = spectral.spectrum(x, fs, window=None)
    _, hann = spectral.spectrum(x, fs, window="hann")
    k = np.argmin(np.abs(f - 1.05))
    assert 0.60 < rect[k] < 0.66  # sinc(1/2) = 0.637: the 36 % loss
    assert 0.82 < hann[k] < 0.88  # Hann scalloping loss ~15 %
    # evaluated at the exact frequency there is no scalloping
    assert spectral.amplitude_at(x, fs, 1.05) == pytest.approx(1.0, abs=0.01)


def test_batched_and_errors():
    fs = 20.0
    t = np.arange(0, 30, 1 / fs)
    x = np.stack([np.cos(2 * np.pi * 0.5 * t), 2 * np.sin(2 * np.pi * 0.5 * t)])
    np.testing.assert_allclose(spectral.amplitude_at(x, fs, 0.5, window=None), [1.0, 2.0],
                               rtol=1e-10)
    with pytest.raises(ValueError, match="NaN"):
        spectral.amplitude_at(np.array([1.0, np.nan, 2.0]), fs, 0.5)
    with pytest.raises(ValueError, match="unknown window"):
        spectral.spectrum(x, fs, window="kaiser")


@pytest.mark.parametrize("n", [2, 3, 10, 101, 18001])
def test_hann_window_is_scipys_to_the_bit(n):
    """The numpy Hann window equals scipy.signal.windows.hann(n, sym=True) exactly."""
    from scipy.signal import windows

    assert np.array_equal(spectral.window(n, "hann"), windows.hann(n, sym=True))
