"""Shared test data of the treadmill tests (test_mocap, test_mocap_real, test_mocap_online): the
stand-in configuration, the seed, and a copy of the real public subset.

A plain module beside the tests (pytest puts ``tests/`` on ``sys.path``), not a test module.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from required import REAL, skip_unless_required

from pedalrepro import paths

#: The stand-in generator's configuration (``mocap`` of config/config.yaml, one run per system).
CFG = {
    "duration_s": 60.0, "sample_rate_hz": 100.0, "marker_noise_m": 0.00015,
    "gaps_per_marker_per_min": 3.0, "max_gap_s": 1.5, "repair_gap_max_s": 0.5,
    "max_runs_per_system": 1, "stand_in_gear_ratios": [1.6, 2.0, 2.4, 2.8],
    "stand_in_cadence_rpm": 75.0,
}
#: The seed of config/config.yaml.
SEED = 20090115
#: The folder ``shared`` beside the clone (CI); a worktree elsewhere may name the folder with
#: ``PEDALREPRO_REAL_SUBSET_DIR`` (tests only: the project never reads ../shared at run time).
SHARED_REAL = Path(os.environ.get("PEDALREPRO_REAL_SUBSET_DIR") or
                   paths.ROOT.parent / "shared" / "reference" / "real-mocap")


def copy_real_subset(dest: Path) -> Path:
    """A copy of the public subset in ``dest`` (skips with the reason when it is absent)."""
    if not SHARED_REAL.is_dir():
        skip_unless_required(REAL, f"real subset not found at {SHARED_REAL} (the folder "
                             "'shared' beside the repository); CI provides it")
    dest.mkdir(parents=True, exist_ok=True)
    for p in SHARED_REAL.iterdir():
        if p.suffix in (".xlsx", ".csv"):
            shutil.copy2(p, dest / p.name)
    return dest
