"""The time-solution file of methods LA, LN, NT and NP (thesis Sec 3.1.2): one format, its keys,
its writer and its reader.

Every method's sweep over the speed-cadence grid is written to
``results/intermediate/time/<method>_<model>.npz`` by :func:`write` (rule scripts
``rules/scripts/linear_time.py`` for LA and LN, ``rules/scripts/nonlinear_time.py`` for NT and
NP, which joins the speed chunks of ``rules/scripts/nonlinear_time_chunk.py`` with
:func:`merge_chunks`), and read back by :func:`read` (the figure registry). Both check the keys:
a file without a key of :data:`REQUIRED`, or with a grid array of the wrong shape, is refused
with the file and the key named.

Keys (``n_v`` speeds, ``n_w`` cadences, ``n_t`` samples of the example runs, ``n_p`` = 6 example
points of :func:`pedalrepro.evaluation.example_points`, ``n_s`` = 6 series cadences):

==========================  ============  ===================================================
key                         shape         meaning
==========================  ============  ===================================================
``speed_m_s``               (n_v,)        forward speeds of the grid
``omega_rad_s``             (n_w,)        cadences of the grid
``roll_amp_rad``            (n_v, n_w)    roll amplitude at the cadence (Hann window, Sec
                                          3.1.2.1.1)
``steer_amp_rad``           (n_v, n_w)    steer amplitude at the cadence
``t_end_s``                 (n_v, n_w)    end of the run (the duration, or the fall)
``fell``                    (n_v, n_w)    bool: the roll angle passed the fall limit
``method``, ``model``       ()            e.g. ``"LA"``, ``"HS"``
``harmonics``               (n_h,)        the harmonics of the pedalling forcing
``sample_rate_hz``          ()            sample rate of the runs
``example_speed_m_s``       (n_p,)        the six numbered points (speed ...
``example_omega_rad_s``     (n_p,)        ... and cadence)
``example_t_s``             (n_t,)        sample times of the example runs and the series
``example_roll_rad``        (n_p, n_t)    roll angle at the six points (NaN after a fall)
``example_steer_rad``       (n_p, n_t)    steer angle at the six points
``series_speed_m_s``        (n_s,)        one-speed series of Figs 3.18/3.19/3.28/3.29 ...
``series_omega_rad_s``      (n_s,)        ... at these cadences
``series_roll_rad``         (n_s, n_t)    roll angle of the series
``series_steer_rad``        (n_s, n_t)    steer angle of the series
==========================  ============  ===================================================

Optional keys (:data:`OPTIONAL`): ``example_t_end_s``, ``example_fell``, ``series_t_end_s``
(every method), ``series_fell`` (NT, NP); ``roll_amp_rect_rad``, ``steer_amp_rect_rad`` (LA, LN:
the amplitude without a window); ``roll_amp_h1_rad``, ``steer_amp_h1_rad``,
``example_roll_h1_rad``, ``example_steer_h1_rad`` (LA: forcing at the cadence only, evaluation
point 2b); ``example_roll_tight_rad``, ``example_steer_tight_rad`` (LN: the example runs at the
tight tolerances); ``n_rhs`` (NT, NP: right-hand-side calls per run).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

__all__ = ["CHUNK_GRID_KEYS", "METHODS", "OPTIONAL", "REQUIRED", "TimeSolutionError", "check",
           "merge_chunks", "read", "write"]

#: The time-solution methods of Sec 3.1.2, analytic and numerical linear (LA, LN), non-linear
#: with the torques (NT) or with the prescribed legs (NP).
METHODS: tuple[str, ...] = ("LA", "LN", "NT", "NP")

#: Required key -> shape, in names of the dimensions (module docstring).
REQUIRED: dict[str, tuple[str, ...]] = {
    "speed_m_s": ("n_v",), "omega_rad_s": ("n_w",),
    "roll_amp_rad": ("n_v", "n_w"), "steer_amp_rad": ("n_v", "n_w"),
    "t_end_s": ("n_v", "n_w"), "fell": ("n_v", "n_w"),
    "method": (), "model": (), "harmonics": ("n_h",), "sample_rate_hz": (),
    "example_speed_m_s": ("n_p",), "example_omega_rad_s": ("n_p",), "example_t_s": ("n_t",),
    "example_roll_rad": ("n_p", "n_t"), "example_steer_rad": ("n_p", "n_t"),
    "series_speed_m_s": ("n_s",), "series_omega_rad_s": ("n_s",),
    "series_roll_rad": ("n_s", "n_t"), "series_steer_rad": ("n_s", "n_t"),
}

#: Optional key -> shape (written by some methods only; module docstring).
OPTIONAL: dict[str, tuple[str, ...]] = {
    "example_t_end_s": ("n_p",), "example_fell": ("n_p",),
    "series_t_end_s": ("n_s",), "series_fell": ("n_s",),
    "roll_amp_rect_rad": ("n_v", "n_w"), "steer_amp_rect_rad": ("n_v", "n_w"),
    "roll_amp_h1_rad": ("n_v", "n_w"), "steer_amp_h1_rad": ("n_v", "n_w"),
    "example_roll_h1_rad": ("n_p", "n_t"), "example_steer_h1_rad": ("n_p", "n_t"),
    "example_roll_tight_rad": ("n_p", "n_t"), "example_steer_tight_rad": ("n_p", "n_t"),
    "n_rhs": ("n_v", "n_w"),
}

#: Grid arrays a chunk of an NT/NP sweep carries (``rules/scripts/nonlinear_time_chunk.py``).
CHUNK_GRID_KEYS: tuple[str, ...] = ("roll_amp_rad", "steer_amp_rad", "t_end_s", "fell", "n_rhs")


class TimeSolutionError(ValueError):
    """A time-solution file or array set that lacks a key or has a wrong shape (the message
    names the file and the key)."""


def check(arrays: Mapping[str, np.ndarray], source: str | Path = "time-solution arrays") -> None:
    """Refuse ``arrays`` unless it has every :data:`REQUIRED` key with consistent shapes.

    Parameters
    ----------
    arrays
        Key -> array, as written by :func:`write` or loaded from the file.
    source
        What to name in the error (the file's path).

    Raises
    ------
    TimeSolutionError
        A required key is missing, a known key's shape disagrees with the grid (``n_v`` from
        ``speed_m_s``, ``n_w`` from ``omega_rad_s``, ``n_t`` from ``example_t_s``, ...), ``fell``
        is not boolean, or ``method`` is not one of :data:`METHODS`.
    """
    missing = [k for k in REQUIRED if k not in arrays]
    if missing:
        raise TimeSolutionError(f"{source}: missing key(s) {', '.join(missing)} of the "
                                "time-solution file (pedalrepro.timesolution.REQUIRED)")
    dims = {"n_v": np.shape(arrays["speed_m_s"])[0], "n_w": np.shape(arrays["omega_rad_s"])[0],
            "n_t": np.shape(arrays["example_t_s"])[0], "n_h": np.shape(arrays["harmonics"])[0],
            "n_p": np.shape(arrays["example_speed_m_s"])[0],
            "n_s": np.shape(arrays["series_speed_m_s"])[0]}
    for key, names in {**REQUIRED, **OPTIONAL}.items():
        if key in arrays:
            want = tuple(dims[n] for n in names)
            if np.shape(arrays[key]) != want:
                raise TimeSolutionError(f"{source}: {key} has shape {np.shape(arrays[key])}, "
                                        f"expected {want} ({', '.join(names) or 'a scalar'})")
    if np.asarray(arrays["fell"]).dtype != bool:
        raise TimeSolutionError(f"{source}: fell is {np.asarray(arrays['fell']).dtype}, "
                                "expected bool")
    if str(arrays["method"]) not in METHODS:
        raise TimeSolutionError(f"{source}: method {str(arrays['method'])!r} is not one of "
                                f"{', '.join(METHODS)}")


def write(path: str | Path, arrays: Mapping[str, np.ndarray]) -> Path:
    """Check ``arrays`` (:func:`check`) and write them, in their order, as a compressed npz."""
    check(arrays, path)
    np.savez_compressed(path, **arrays)
    return Path(path)


def read(path: str | Path) -> dict[str, np.ndarray]:
    """Every array of a time-solution file, after :func:`check` (the error names the file)."""
    with np.load(path, allow_pickle=False) as d:
        arrays = {k: d[k] for k in d.files}
    check(arrays, path)
    return arrays


def merge_chunks(parts: Iterable[Mapping[str, np.ndarray]], speed_m_s: np.ndarray,
                 omega_rad_s: np.ndarray, method: str, model: str, harmonics: np.ndarray,
                 sample_rate_hz: float, source: str = "") -> dict[str, np.ndarray]:
    """The time-solution arrays of an NT/NP sweep from its speed chunks.

    Each chunk holds ``speed_index`` (its rows of the speed grid) and :data:`CHUNK_GRID_KEYS`;
    exactly one (chunk 0) also holds the ``example_*`` and ``series_*`` arrays.

    Raises
    ------
    TimeSolutionError
        The chunks do not cover the speed grid once, or not exactly one carries the examples.
    """
    parts = list(parts)
    order = np.concatenate([p["speed_index"] for p in parts])
    if not np.array_equal(np.sort(order), np.arange(np.size(speed_m_s))):
        raise TimeSolutionError(f"chunks of {source or method + '_' + model} do not cover the "
                                "speed grid")
    grid = {k: np.concatenate([p[k] for p in parts])[np.argsort(order)]
            for k in CHUNK_GRID_KEYS}
    first = [p for p in parts if "example_roll_rad" in p]
    if len(first) != 1:
        raise TimeSolutionError(f"chunks of {source or method + '_' + model}: {len(first)} carry "
                                "the example runs, expected exactly one (chunk 0)")
    examples = {k: a for k, a in first[0].items() if k.startswith(("example_", "series_"))}
    return dict(speed_m_s=speed_m_s, omega_rad_s=omega_rad_s, method=method, model=model,
                harmonics=np.asarray(harmonics), sample_rate_hz=sample_rate_hz, **examples,
                **grid)
