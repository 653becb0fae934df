"""The measured closed-loop spectra of the thesis's CF condition (Moore's MotionCapture figures).

Four MATLAB figure files of ``github.com/moorepants/MotionCapture`` (commit ``e46740b``,
``MatlabCode/``, registry ``data/registry_spectra.txt``: raw URLs at that commit, sha256):
rider Jason (rider 3) on the Batavus Browser, hands on the handlebars, normal pedalling, the
thesis's system CF, one run per belt speed (2, 3, 4, 5, 10, 15, 20, 25, 30 km/h; a second steer
set at 5-30 km/h). Each axis holds the amplitude spectrum, a grey dotted line at the open-loop
weave frequency and a black line at the cadence. Fetched and verified like the public subset
(:mod:`pedalrepro.mocap.fetch`: offline from ``$PEDALREPRO_DATA_DIR``).

Units and normalisation (the files do not state them; established from evidence, book page
*Deviations and ambiguities*):

- the spectrum is Moore's ``freqampl`` (MotionCapture ``MatlabCode/PCAgui6.m``): mean removed,
  ``ampl = 2 |fft(y)| / n`` over the first ``n/2`` bins, no window, plotted against
  ``Fs/2 * linspace(0, 1, n/2)``. The files' frequency step, 0.0166722 Hz = 100 Hz / 5998,
  is exactly that axis for ``n = 6000`` samples at 100 Hz (60 s): a bin ``k`` is drawn at
  ``k Fs/(n-2)`` instead of ``k Fs/n`` (0.033 % high; the bin index is unaffected), and the
  zero-mean signal shows in the DC values (1e-17);
- ``2|X|/n`` is the amplitude of a sinusoid exactly on a bin: the thesis's measure
  (Sec 3.1.2.1.1) up to its Hann window (an unwindowed DFT gives the same peak on a bin and a
  lower one between bins, by up to 36 %);
- the y label says deg, but the values are radians: steer 0.011-0.014 at the cadence at
  25-30 km/h is the size of Table 4.1's measured hands-free steer (0.010-0.031 rad); in degrees
  it would be 2e-4 rad, below the markers' resolution.

Every value read here is labelled :data:`LABEL`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pooch

from .. import paths
from . import fetch

__all__ = [
    "REGISTRY_SPECTRA", "DATA_FILES", "LABEL", "FILES", "STEER_SECOND", "SpectraFormatError",
    "make_pooch", "fetch_files", "SpeedSpectrum", "read_figure", "read_all", "cadence_table",
]

REGISTRY_SPECTRA: Path = paths.DATA / "registry_spectra.txt"
#: Read at run time (pedalrepro.dependencies: the rules' code inputs).
DATA_FILES: tuple[str, ...] = ("data/registry_spectra.txt",)
#: How every value from these files is labelled.
LABEL = "measured (published spectra)"
#: The all-speed files per coordinate.
FILES: dict[str, str] = {
    "roll": "pedalingROLLfrequencyallspeeds.fig",
    "steer": "pedalingsteeringfrequencyallspeeds.fig",
    "yaw": "pedalingYAWfrequencyallspeeds.fig",
}
#: The second steer set (5-30 km/h).
STEER_SECOND = "pedalingsteeringfrequency.fig"
_SPEED = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*\[km/h\]\s*$")


class SpectraFormatError(ValueError):
    """A figure file that does not have the expected structure (the message names it)."""


def make_pooch(base_url: str | None = None, path: str | Path | None = None) -> pooch.Pooch:
    """The spectra's :class:`pooch.Pooch` (data folder ``fetch.data_dir()``; ``base_url``
    replaces the registry's URLs, e.g. a mirror or a local test server)."""
    return fetch.make_public_pooch(REGISTRY_SPECTRA, base_url=base_url,
                                   path=path or fetch.data_dir())


def fetch_files(pup: pooch.Pooch | None = None, progressbar: bool = False,
                events: list[str] | None = None) -> dict[str, Path]:
    """All four figure files, each verified against its sha256 (downloaded when missing).

    Raises
    ------
    fetch.DataUnavailableError, fetch.HashMismatchError
        A file cannot be had or does not match its hash.
    """
    pup = pup or make_pooch()
    return {name: fetch.fetch(name, pup, progressbar, events) for name in sorted(pup.registry)}


@dataclass(frozen=True)
class SpeedSpectrum:
    """One axis of a figure: one run at one belt speed.

    ``frequency_hz`` and ``amplitude_rad`` as drawn (``freqampl``'s axis, module docstring);
    ``cadence_hz`` and ``weave_hz`` the vertical lines.
    """

    speed_kmh: float
    frequency_hz: np.ndarray
    amplitude_rad: np.ndarray
    cadence_hz: float
    weave_hz: float

    def at_cadence(self, harmonic: int = 1) -> tuple[float, float]:
        """Amplitude at ``harmonic`` x the cadence: the nearest bin (as the thesis reads a
        spectrum) and the largest value within 2 bins of it (rad)."""
        f = harmonic * self.cadence_hz
        i = int(np.argmin(np.abs(self.frequency_hz - f)))
        lo, hi = max(i - 2, 0), min(i + 3, len(self.amplitude_rad))
        return float(self.amplitude_rad[i]), float(np.max(self.amplitude_rad[lo:hi]))


def _children(obj) -> list:
    ch = getattr(obj, "children", None)
    if ch is None:
        return []
    if isinstance(ch, np.ndarray):
        return list(ch.ravel())
    return [ch]


def read_figure(path: str | Path) -> dict[float, SpeedSpectrum]:
    """The spectra of one figure file, by belt speed (km/h).

    Raises
    ------
    SpectraFormatError
        The file is not a MATLAB figure with per-speed axes of spectrum + two vertical lines.
    """
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    path = Path(path)
    try:
        root = loadmat(str(path), squeeze_me=True, struct_as_record=False)["hgS_070000"]
    except (KeyError, ValueError, OSError, MatReadError) as exc:
        raise SpectraFormatError(f"{path}: not a MATLAB figure file ({exc})") from exc
    out: dict[float, SpeedSpectrum] = {}
    for ax in _children(root):
        if getattr(ax, "type", "") != "axes":
            continue
        lines, speed = [], None
        for c in _children(ax):
            props = c.properties
            if c.type == "text":
                m = _SPEED.match(str(np.atleast_1d(getattr(props, "String", ""))[0]))
                if m:
                    speed = float(m.group(1))
            elif c.type in ("graph2d.lineseries", "line"):
                lines.append((np.atleast_1d(np.asarray(props.XData, float)),
                              np.atleast_1d(np.asarray(props.YData, float)),
                              np.atleast_1d(np.asarray(getattr(props, "Color", [0, 0, 0]),
                                                       float))))
        spectra = [ln for ln in lines if ln[0].size > 2]
        vertical = [ln for ln in lines if ln[0].size == 2 and ln[0][0] == ln[0][1]]
        if speed is None or len(spectra) != 1 or len(vertical) != 2:
            raise SpectraFormatError(
                f"{path}: an axis without a speed label, one spectrum and two vertical lines "
                f"(speed {speed}, {len(spectra)} spectra, {len(vertical)} vertical lines)")
        x, y, _ = spectra[0]
        keep = np.isfinite(x) & np.isfinite(y)
        # drop a trailing wrap-around (the 2 km/h axis ends with x = 0)
        stop = int(np.argmax(np.diff(x[keep]) <= 0)) + 1 if np.any(np.diff(x[keep]) <= 0) \
            else int(keep.sum())
        x, y = x[keep][:stop], y[keep][:stop]
        grey = [v for v in vertical if v[2].max() > 0.1]  # weave: grey [0.4 0.4 0.4]
        black = [v for v in vertical if v[2].max() <= 0.1]  # cadence: black
        if len(grey) != 1 or len(black) != 1:
            raise SpectraFormatError(f"{path}, {speed} km/h: cannot tell the weave line (grey) "
                                     "from the cadence line (black)")
        out[speed] = SpeedSpectrum(speed, x, y, float(black[0][0][0]), float(grey[0][0][0]))
    if not out:
        raise SpectraFormatError(f"{path}: no spectrum axes")
    return out


def read_all(files: dict[str, Path]) -> dict[str, dict[float, SpeedSpectrum]]:
    """Roll, steer and yaw spectra (the all-speed files) and ``steer_second``, by speed."""
    out = {}
    for coord, name in FILES.items():
        if name not in files:
            raise KeyError(f"spectra: {name} missing (have {sorted(files)})")
        out[coord] = read_figure(files[name])
    if STEER_SECOND in files:
        out["steer_second"] = read_figure(files[STEER_SECOND])
    return out


def cadence_table(spectra: dict[str, dict[float, SpeedSpectrum]]):
    """One row per speed: cadence (Hz, rpm), weave line (Hz) and the roll, steer, yaw
    amplitudes at the cadence (nearest bin and peak within 2 bins), labelled :data:`LABEL`.

    Raises ``ValueError`` when the coordinates' cadence lines disagree at a speed.
    """
    import pandas as pd

    rows = []
    for speed in sorted(spectra["roll"]):
        row = {"system": "CF", "speed_kmh": speed}
        cad = {c: spectra[c][speed].cadence_hz for c in ("roll", "steer", "yaw")
               if speed in spectra[c]}
        if max(cad.values()) - min(cad.values()) > 1e-9:
            raise ValueError(f"spectra at {speed} km/h: cadence lines differ {cad}")
        row["cadence_hz"] = cad["roll"]
        row["cadence_rpm"] = 60.0 * cad["roll"]
        row["weave_hz"] = spectra["roll"][speed].weave_hz
        row["frequency_step_hz"] = float(np.median(np.diff(spectra["roll"][speed].frequency_hz)))
        for c in ("roll", "steer", "yaw"):
            near, peak = spectra[c][speed].at_cadence()
            row[f"{c}_nearest_rad"] = near
            row[f"{c}_peak2_rad"] = peak
        row["source"] = LABEL
        rows.append(row)
    return pd.DataFrame(rows)
