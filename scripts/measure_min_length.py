"""Measure the shortest analysable run length: cadence amplitudes of excerpts of run 3045
against those of the whole 60 s record, the measurement behind the minimum record length that
``pedalrepro.mocap.runs`` refuses below (``MIN_SEGMENT_S``).

    PEDALREPRO_DATA_DIR=/path/to/3045_X.xlsx... python scripts/measure_min_length.py

For each excerpt length ``T`` every excerpt starting at 0, 2.5, 5, ... s that fits in the record
is analysed exactly as a run (``pedalrepro.mocap.runs.analyse_loaded`` without the length check:
kinematics, 12 Hz low-pass, cadence from the right foot, Hann DFT at the exact cadence); the
table gives the median and largest relative error of the roll and steer amplitudes against the
whole record's, and the shortest length whose median error of both stays within 5 % (the last
printed digit of Table 4.1's measured amplitudes, 0.0005 rad of 0.011 rad).
``MIN_SEGMENT_S`` (runs.py) and ``mocap.duration_s``'s minimum (config/schema.yaml) cite the
result (measured 2026-12-01: 20 s; median 4.7 % roll, 1.3 % steer; largest 10.3 %, 6.8 %).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from unittest import mock

import numpy as np

from pedalrepro.mocap import runs

LENGTHS_S = (1.0, 2.0, 3.0, 5.0, 7.5, 10.0, 12.5, 15.0, 20.0, 30.0, 45.0)
STEP_S = 2.5
TOLERANCE = 0.05


def excerpt_errors(run, whole: dict[str, float], length_s: float, step_s: float = STEP_S
                   ) -> np.ndarray:
    """Relative errors ``(n_excerpts, 2)`` of roll and steer amplitudes of every excerpt of
    ``length_s`` starting every ``step_s`` (NaN where the excerpt is refused)."""
    fs = run.sample_rate_hz
    n = int(round(length_s * fs))
    out = []
    for i0 in range(0, len(run.t_s) - n + 1, int(round(step_s * fs))):
        part = runs.excerpt(run, i0, i0 + n)
        try:
            with mock.patch.object(runs, "check_length", lambda r: len(r.t_s) / fs):
                a = runs.analyse_loaded(part)
            out.append([a.amplitudes[k] / whole[k] - 1 for k in ("roll_amp_rad",
                                                                   "steer_amp_rad")])
        except (ValueError, IndexError):
            out.append([np.nan, np.nan])
    return np.asarray(out, float)


def main() -> int:
    folder = Path(os.environ.get("PEDALREPRO_DATA_DIR", ""))
    source = folder / "3045_X.xlsx"
    if not source.is_file():
        print(f"{source} not found: set PEDALREPRO_DATA_DIR to the folder of run 3045's files",
              file=sys.stderr)
        return 2
    run = runs.load_run(source)
    whole = runs.analyse_loaded(run).amplitudes
    print(f"run 3045, whole {len(run.t_s) / run.sample_rate_hz:g} s: roll "
          f"{whole['roll_amp_rad']:.5f} rad, steer {whole['steer_amp_rad']:.5f} rad")
    print("length_s  excerpts  refused  roll_median  roll_max  steer_median  steer_max")
    chosen = None
    for length in LENGTHS_S:
        err = excerpt_errors(run, whole, length)
        ok = ~np.isnan(err[:, 0])
        a = np.abs(err[ok])
        print(f"{length:8g}  {len(err):8d}  {int((~ok).sum()):7d}  {np.median(a[:, 0]):11.3f}  "
              f"{a[:, 0].max():8.3f}  {np.median(a[:, 1]):12.3f}  {a[:, 1].max():9.3f}")
        median = float(np.median(a, axis=0).max()) if ok.any() else np.inf
        if chosen is None and ok.all() and median <= TOLERANCE:
            chosen = length
        elif median > TOLERANCE or not ok.all():
            chosen = None  # a longer length fails again: not yet the minimum
    print(f"shortest length with every excerpt analysed and a median error within "
          f"{TOLERANCE:.0%}: {chosen} s (MIN_SEGMENT_S = {runs.MIN_SEGMENT_S:g} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
