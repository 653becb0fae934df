"""The relative difference RD of two response amplitudes (thesis Eq 3.26, Sec 3.1.3): a leaf
module (numpy only), so that the RD maps' figures do not depend on the solution methods of
:mod:`pedalrepro.evaluation`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["relative_difference"]


def relative_difference(reference, other) -> np.ndarray:
    """Eq 3.26 in percent; NaN where the reference amplitude is zero (no forcing, w = 0)."""
    ref = np.abs(np.asarray(reference, float))
    oth = np.abs(np.asarray(other, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        rd = np.abs((ref - oth) / ref) * 100.0
    return np.where(ref > 0, rd, np.nan)
