"""Linear bicycle(-rider) models and their eigen analysis (Sec 3.1.1, 3.1.2.2, Appendix B).

The linearised roll-steer equations (Eq 3.1)

    M q'' + v C1 q' + (g K0 + v^2 K2) q = f,   q = [roll, steer]

for the Meijaard et al. (2007) benchmark bicycle (matrices computed from its published
parameters with dynamicisttoolkit, not re-derived) and the thesis's four bicycle-rider models
HS, CF, HR, CR (Appendix B matrices, which the thesis itself uses as inputs).

Eigenvalues versus speed are tracked continuously from one speed to the next and named after
the modes of Meijaard et al. (2007): ``weave`` (the pair that is oscillatory at moderate
speed), ``capsize`` (the real root closest to zero at high speed) and ``caster`` (the most
negative real root). Characteristic speeds are found by root finding (``brentq``) on the real
part of the tracked eigenvalue, not by reading the grid.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import params
from .params import LinearModel

__all__ = [
    "MODEL_NAMES", "MODE_NAMES", "benchmark_model", "linear_model", "bicycle_of", "state_matrix",
    "eigenvalues", "EigenSweep", "eigen_sweep", "max_real_part", "branch_crossings",
    "stable_ranges", "EigenSummary", "summarise", "oscillatory_onset",
]

#: Model names accepted by :func:`linear_model`.
MODEL_NAMES: tuple[str, ...] = params.LINEAR_MODELS
#: Mode names, in the order of the columns of :attr:`EigenSweep.eigenvalues`.
MODE_NAMES: tuple[str, ...] = ("weave", "weave", "capsize", "caster")


def benchmark_model(parameter_file: str = "benchmark") -> LinearModel:
    """The linear Whipple model of a bicycle in benchmark parameters (Meijaard et al. 2007).

    Uses ``dtk.bicycle.benchmark_par_to_canonical`` (dynamicisttoolkit) on the parameters of
    ``data/parameters/<parameter_file>.yaml``.

    Parameters
    ----------
    parameter_file
        Stem of a parameter file with a benchmark ``parameters:`` mapping.

    Returns
    -------
    LinearModel
        ``M``, ``C1``, ``K0``, ``K2`` and ``g`` (Eq 3.1).
    """
    from dtk.bicycle import benchmark_par_to_canonical

    p = params.benchmark_parameters(parameter_file)
    m, c1, k0, k2 = benchmark_par_to_canonical(p)
    name = "benchmark" if parameter_file == "benchmark" else parameter_file
    return LinearModel(name, np.asarray(m, float), np.asarray(c1, float),
                       np.asarray(k0, float), np.asarray(k2, float), g=float(p.get("g", 9.81)))


def linear_model(name: str) -> LinearModel:
    """The linear model ``"benchmark"`` (Meijaard 2007) or ``"HS"``, ``"CF"``, ``"HR"``, ``"CR"``.

    Parameters
    ----------
    name
        One of :data:`MODEL_NAMES`.

    Returns
    -------
    LinearModel
        The matrices of Eq 3.1 (Appendix B for the thesis models).
    """
    if name == "benchmark":
        return benchmark_model("benchmark")
    if name in params.MODELS:
        return params.appendix_b_model(name)
    raise KeyError(f"unknown linear model {name!r}: expected one of {MODEL_NAMES}")


def bicycle_of(name: str) -> str:
    """The bicycle (``"hybrid"``, ``"city"``, ``"benchmark"``) whose legs drive model ``name``."""
    if name == "benchmark":
        return "benchmark"
    return params.BICYCLE_OF_MODEL[name]


def state_matrix(model: LinearModel, speed_m_s: np.ndarray | float) -> np.ndarray:
    """State matrix ``A(v)`` of ``x' = A x`` with ``x = [roll, steer, roll', steer']`` (Eq 3.1).

    Parameters
    ----------
    model
        The linear model.
    speed_m_s
        Forward speed(s), any shape ``S``.

    Returns
    -------
    numpy.ndarray
        Shape ``S + (4, 4)``.
    """
    v = np.asarray(speed_m_s, dtype=float)[..., None, None]
    minv = np.linalg.inv(model.M)
    stiff = model.g * model.K0 + v**2 * model.K2
    damp = v * model.C1
    a = np.zeros(v.shape[:-2] + (4, 4))
    a[..., 0:2, 2:4] = np.eye(2)
    a[..., 2:4, 0:2] = -minv @ stiff
    a[..., 2:4, 2:4] = -minv @ damp
    return a


def eigenvalues(model: LinearModel, speed_m_s: np.ndarray | float) -> np.ndarray:
    """Eigenvalues of ``A(v)`` (unsorted), shape ``S + (4,)`` (1/s)."""
    return np.linalg.eigvals(state_matrix(model, speed_m_s))


def _track(eig: np.ndarray) -> np.ndarray:
    """Reorder the columns of ``eig`` (n_v, 4) so that each column is a continuous branch."""
    from scipy.optimize import linear_sum_assignment  # here: sweep jobs never track branches

    out = np.empty_like(eig)
    out[0] = eig[0][np.lexsort((eig[0].imag, eig[0].real))]
    for i in range(1, len(eig)):
        prev = out[i - 1]
        if i >= 2:  # linear prediction follows branches through near-crossings
            prev = 2 * out[i - 1] - out[i - 2]
        cost = np.abs(prev[:, None] - eig[i][None, :])
        _, col = linear_sum_assignment(cost)
        out[i] = eig[i][col]
    return out


@dataclass
class EigenSweep:
    """Eigenvalues versus speed with the branches tracked and named (Fig 3.6, 3.9).

    Attributes
    ----------
    model
        Model name.
    speed_m_s
        Speeds (n_v,).
    eigenvalues
        Tracked eigenvalues (n_v, 4); column ``j`` is the branch named ``names[j]``.
    names
        ``("weave", "weave", "capsize", "caster")`` in some column order.
    """

    model: str
    speed_m_s: np.ndarray
    eigenvalues: np.ndarray
    names: tuple[str, ...] = field(default_factory=tuple)

    def branch(self, name: str) -> np.ndarray:
        """Columns of the branches called ``name`` (n_v, k)."""
        cols = [j for j, n in enumerate(self.names) if n == name]
        return self.eigenvalues[:, cols]

    def weave_frequency_rad_s(self) -> np.ndarray:
        """Imaginary part of the weave eigenvalue (0 where the weave branch is real) (n_v,)."""
        return np.abs(self.branch("weave").imag).max(axis=1)


def eigen_sweep(model: LinearModel, speed_m_s: np.ndarray) -> EigenSweep:
    """Eigenvalues over a speed grid, tracked and named (Sec 3.2.1, Fig 3.6, 3.9).

    Names are given at the highest speed of the grid, where the benchmark-like models have an
    oscillatory pair (weave), a real root near zero (capsize) and a strongly negative real root
    (caster), and follow each branch down to the lowest speed.

    Parameters
    ----------
    model
        The linear model.
    speed_m_s
        Increasing speeds; a fine grid (0.01 m/s) keeps the tracking unambiguous.
    """
    v = np.asarray(speed_m_s, dtype=float)
    if v.ndim != 1 or len(v) < 3 or np.any(np.diff(v) <= 0):
        raise ValueError("speed_m_s must be an increasing 1-D grid with at least 3 speeds")
    eig = _track(eigenvalues(model, v))
    last = eig[-1]
    order = np.argsort(np.abs(last.imag))[::-1]
    names = [""] * 4
    complex_cols = [j for j in order if abs(last[j].imag) > 1e-9]
    if len(complex_cols) >= 2:
        names[complex_cols[0]] = names[complex_cols[1]] = "weave"
        rest = [j for j in range(4) if not names[j]]
    else:  # no oscillatory pair at the top speed: the two largest real parts form the weave
        by_real = list(np.argsort(last.real)[::-1])
        # weave = the pair closest to each other among the three largest (heuristic)
        names[by_real[0]] = names[by_real[1]] = "weave"
        rest = by_real[2:]
    rest = sorted(rest, key=lambda j: last[j].real)
    names[rest[0]] = "caster"
    names[rest[1]] = "capsize"
    return EigenSweep(model.name, v, eig, tuple(names))


def max_real_part(model: LinearModel, speed_m_s: float) -> float:
    """Largest real part of the eigenvalues at one speed (1/s); < 0 means self-stable."""
    return float(eigenvalues(model, speed_m_s).real.max())


def _branch_root(model: LinearModel, sweep: EigenSweep, col: int, i: int) -> float:
    """Speed where branch ``col`` has zero real part, between grid speeds ``i`` and ``i+1``."""
    from scipy.optimize import brentq
    v = sweep.speed_m_s
    lam = sweep.eigenvalues[:, col]

    def f(speed: float) -> float:
        guess = np.interp(speed, v[i:i + 2], lam.real[i:i + 2]) + 1j * np.interp(
            speed, v[i:i + 2], lam.imag[i:i + 2])
        e = eigenvalues(model, speed)
        return float(e[np.argmin(np.abs(e - guess))].real)

    return float(brentq(f, v[i], v[i + 1], xtol=1e-12, rtol=1e-14))


def branch_crossings(model: LinearModel, sweep: EigenSweep, name: str) -> list[tuple[float, str]]:
    """Speeds where a branch called ``name`` crosses zero real part, with the direction.

    Returns
    -------
    list of (speed_m_s, direction)
        ``direction`` is ``"stabilises"`` (real part goes from + to -) or ``"destabilises"``.
        For the weave pair each crossing is reported once.
    """
    out: list[tuple[float, str]] = []
    for col in [j for j, n in enumerate(sweep.names) if n == name]:
        re = sweep.eigenvalues[:, col].real
        idx = np.nonzero(np.sign(re[:-1]) * np.sign(re[1:]) < 0)[0]
        for i in idx:
            speed = _branch_root(model, sweep, col, i)
            direction = "stabilises" if re[i] > 0 else "destabilises"
            if not any(abs(speed - s) < 1e-6 and d == direction for s, d in out):
                out.append((speed, direction))
    return sorted(out)


def stable_ranges(model: LinearModel, speed_m_s: np.ndarray) -> list[tuple[float, float]]:
    """Self-stable speed intervals (all real parts negative), ends refined with ``brentq``.

    An interval reaching the end of the grid is reported with that grid end.
    """
    from scipy.optimize import brentq

    v = np.asarray(speed_m_s, dtype=float)
    g = eigenvalues(model, v).real.max(axis=-1)
    stable = g < 0
    ranges = []
    i = 0
    while i < len(v):
        if not stable[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(v) and stable[j + 1]:
            j += 1
        lo = v[i] if i == 0 else brentq(lambda s: max_real_part(model, s), v[i - 1], v[i],
                                         xtol=1e-12)
        hi = v[j] if j == len(v) - 1 else brentq(lambda s: max_real_part(model, s), v[j],
                                                 v[j + 1], xtol=1e-12)
        ranges.append((float(lo), float(hi)))
        i = j + 1
    return ranges


@dataclass
class EigenSummary:
    """Characteristic speeds of one model (a row of ``eigen_summary.csv``).

    ``None`` where a quantity does not exist.
    """

    model: str
    weave_speed_m_s: float | None
    capsize_speed_m_s: float | None
    stable_from_m_s: float | None
    stable_to_m_s: float | None
    weave_frequency_at_weave_speed_rad_s: float | None
    note: str = ""


def summarise(model: LinearModel, speed_m_s: np.ndarray) -> EigenSummary:
    """Weave speed, capsize speed, self-stable range and weave frequency (Sec 3.2.1).

    Weave speed: the lowest speed where the weave branch stabilises (real part + to -). Capsize
    speed: the lowest speed above it where the capsize branch destabilises. The weave frequency
    is the imaginary part of the weave eigenvalue at the weave speed (``None`` when the weave
    branch is still real there, as for model CF).
    """
    sweep = eigen_sweep(model, speed_m_s)
    weave = [s for s, d in branch_crossings(model, sweep, "weave") if d == "stabilises"]
    weave_speed = weave[0] if weave else None
    capsize = [s for s, d in branch_crossings(model, sweep, "capsize")
               if d == "destabilises" and (weave_speed is None or s > weave_speed)]
    capsize_speed = capsize[0] if capsize else None
    ranges = stable_ranges(model, speed_m_s)
    stable_from, stable_to = ranges[0] if ranges else (None, None)
    freq = None
    notes = []
    if weave_speed is not None:
        e = eigenvalues(model, weave_speed)
        k = np.argmin(np.abs(e.real))
        freq = float(abs(e[k].imag)) if abs(e[k].imag) > 1e-9 else None
        if freq is None:
            notes.append(f"the weave branch is still a real root where it stabilises "
                         f"({weave_speed:.2f} m/s); it turns oscillatory at a higher speed")
    if not ranges:
        caps = sweep.branch("capsize").real[:, 0]
        if np.all(caps > 0):
            notes.append("no self-stable range: the capsize root is positive at every speed")
        else:
            notes.append("no self-stable range")
    return EigenSummary(model.name, weave_speed, capsize_speed, stable_from, stable_to, freq,
                        "; ".join(notes))


def oscillatory_onset(model: LinearModel, sweep: EigenSweep) -> float | None:
    """Lowest speed above which the weave branch is an oscillatory (complex) pair.

    Found by bisection on the sign of the discriminant (complex or real pair), to 1e-9 m/s.
    """
    imag = sweep.weave_frequency_rad_s()
    v = sweep.speed_m_s
    # last real-to-complex transition of the weave pair
    idx = np.nonzero((imag[:-1] < 1e-9) & (imag[1:] >= 1e-9))[0]
    if len(idx) == 0:
        return None
    i = idx[-1]
    lo, hi = v[i], v[i + 1]
    ref = sweep.branch("weave")[i + 1, 0]

    def is_complex(speed: float) -> bool:
        e = eigenvalues(model, speed)
        near = e[np.argsort(np.abs(e - ref))[:2]]
        return bool(np.abs(near.imag).max() > 1e-12)

    while hi - lo > 1e-9:
        mid = 0.5 * (lo + hi)
        if is_complex(mid):
            hi = mid
        else:
            lo = mid
    return float(hi)
