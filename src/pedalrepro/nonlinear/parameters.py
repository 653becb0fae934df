"""Parameter sets of the non-linear models: benchmark, HR (hybrid) and CR (city), rigid rider.

Bicycle + rider benchmark parameters come from BicycleParameters (Moore's tool) reading the
copies in ``data/parameters/bicycleparameters``; the thesis's modifications (cranks, the city
bicycle's lowered seat, Sec 2.1.1 and 3.1.1.3) and the split of the legs into separate bodies
(method NP) are applied here. Every assumption is listed in
``data/parameters/nonlinear_models.yaml``.
"""

from __future__ import annotations

import contextlib
import io
import warnings
from functools import cache

import numpy as np

from .. import legs, params, paths
from . import model as _model

#: Models with a non-linear counterpart here. HS and CF are substitutes (rigid-rider body plus a
#: linear correction to Appendix B, :mod:`pedalrepro.nonlinear.substitute`): no arm loops.
NONLINEAR_MODELS: tuple[str, ...] = ("benchmark", "HS", "CF", "HR", "CR")


def settings() -> dict:
    """``data/parameters/nonlinear_models.yaml``."""
    return params.read_yaml(paths.PARAMETERS / "nonlinear_models.yaml")


def _inertia(p: dict, body: str) -> np.ndarray:
    i = np.zeros((3, 3))
    i[0, 0], i[1, 1], i[2, 2] = p[f"I{body}xx"], p[f"I{body}yy"], p[f"I{body}zz"]
    i[0, 2] = i[2, 0] = p.get(f"I{body}xz", 0.0)
    return i


def _parallel(m: float, r: np.ndarray) -> np.ndarray:
    """Parallel-axis term ``m (|r|^2 I - r r^T)``."""
    return m * (r @ r * np.eye(3) - np.outer(r, r))


@cache
def _bicycleparameters(name: str, rider: bool) -> tuple[dict, dict]:
    """(bicycle-only, bicycle+rider) benchmark parameters from BicycleParameters."""
    import bicycleparameters as bp

    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        bike = bp.Bicycle(name, pathToData=str(paths.PARAMETERS / "bicycleparameters"),
                          forceRawCalc=name == "Stratos")
        alone = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
        both = dict(alone)
        if rider:
            bike.add_rider("Jason", reCalc=True)
            both = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
    return ({k: float(v) for k, v in alone.items()}, {k: float(v) for k, v in both.items()})


def _combine(parts: list[tuple[float, np.ndarray, np.ndarray]]):
    """Total mass, COM and central inertia of (mass, com (3,), central inertia) parts."""
    m = sum(p[0] for p in parts)
    com = sum(p[0] * p[1] for p in parts) / m
    inertia = sum(p[2] + _parallel(p[0], p[1] - com) for p in parts)
    return m, com, inertia


def _set_body_b(p: dict, m: float, com: np.ndarray, inertia: np.ndarray) -> dict:
    out = dict(p)
    out.update(mB=m, xB=com[0], zB=com[2], IBxx=inertia[0, 0], IByy=inertia[1, 1],
               IBzz=inertia[2, 2], IBxz=inertia[0, 2])
    return out


def _body_b(p: dict) -> tuple[float, np.ndarray, np.ndarray]:
    return p["mB"], np.array([p["xB"], p.get("yB", 0.0), p["zB"]]), _inertia(p, "B")


def bottom_bracket_m(model: str) -> np.ndarray:
    """Crank axis A in the benchmark frame (x forward, z down, rear contact origin), m."""
    s = settings()
    bike = s["models"][model]["bicycle"]
    bb = s["bottom_bracket"][bike]
    r_r = bicycle_rider(model)["rR"]
    return np.array([np.sqrt(bb["lcs"] ** 2 - (r_r - bb["hbb"]) ** 2), 0.0, -bb["hbb"]])


@cache
def bicycle_rider(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of a model with the rider and legs lumped rigidly into body B.

    ``"benchmark"``: Meijaard et al. (2007) unchanged. ``"HR"``/``"CR"`` (and the bodies of the
    substitutes ``"HS"``/``"CF"``): Stratos/Browser + rider Jason + two 0.2 kg cranks at the
    crank axis; on the city bicycle the rider is lowered 0.05 m along the seat tube
    (0.77 -> 0.72 m, Sec 2.1.1) unless ``original_seat`` (Fig E.1).
    """
    s = settings()
    if model not in s["models"]:
        raise KeyError(f"no non-linear model {model!r}: expected one of {NONLINEAR_MODELS}")
    if model == "benchmark":
        return params.benchmark_parameters("benchmark")
    spec = s["models"][model]
    alone, both = _bicycleparameters(spec["bicycle"], spec["rider"])
    a = s["assumptions"]
    frame = _body_b(alone)
    total = _body_b(both)
    # the rider alone = total - bicycle frame (inverse parallel-axis combination)
    m_r = total[0] - frame[0]
    com_r = (total[0] * total[1] - frame[0] * frame[1]) / m_r
    i_r = (total[2] + _parallel(total[0], total[1] - total[1]) - frame[2]
           - _parallel(frame[0], frame[1] - total[1]) - _parallel(m_r, com_r - total[1]))
    parts = [frame]
    geom = legs.leg_geometry(spec["legs"], a["leg_com_model"])
    if spec["legs"] == "city" and a["lower_city_rider_along_seat_tube"] and not original_seat:
        original = params.legs()["seat_geometry"]["city"]["original_seat_tube_plus_post_m"]
        drop = original - geom.seat_tube_plus_post_m
        lam = geom.seat_tube_angle_rad
        com_r = com_r + drop * np.array([np.cos(lam), 0.0, np.sin(lam)])
    parts.append((m_r, com_r, i_r))
    out = dict(both)
    if a["add_cranks"]:
        bb = s["bottom_bracket"][spec["bicycle"]]
        a_pt = np.array([np.sqrt(bb["lcs"] ** 2 - (both["rR"] - bb["hbb"]) ** 2), 0.0, -bb["hbb"]])
        _, _, mean, _ = _leg_revolution(geom, a_pt, both["lam"], both["rR"], 2 * np.pi, 256)
        parts += [p for name, p in zip(_model.LEG_BODIES, mean, strict=True)
                  if name.startswith("crank")]
    return _set_body_b(out, *_combine(parts))


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


def leg_bodies(model: str, cadence_rad_s: float, samples: int = 256):
    """Prescribed leg motion of a model in SymBRiM's rear-frame coordinates.

    Returns
    -------
    (leg_params, spec, mean_parts)
        ``leg_params``: ``<body>_y``, ``<body>_m``, ``<body>_I`` for :data:`model.LEG_BODIES`;
        ``spec``: ``t -> s`` (positions, rates, accelerations in the generated ``SPEC`` order,
        from a Fourier series of one revolution, ``samples`` per revolution, exact to rounding
        for the band-limited four-bar motion); ``mean_parts``: the revolution-averaged
        (mass, com, inertia) of each body in the benchmark frame, to remove from body B.
    """
    s = settings()
    geom = legs.leg_geometry(s["models"][model]["legs"], s["assumptions"]["leg_com_model"])
    bench = bicycle_rider(model)
    omega = float(cadence_rad_s)
    leg_params, signals, mean_parts, _ = _leg_revolution(
        geom, bottom_bracket_m(model), bench["lam"], bench["rR"], omega, samples)
    # Fourier series x(t) = sum_n Re(c_n e^{i n w t}); the crank angles also turn at -omega.
    slope = np.zeros(signals.shape[0])
    slope[[3 * k + 2 for k, n in enumerate(_model.LEG_BODIES) if n.startswith("crank")]] = -omega
    t = 2 * np.pi / omega * np.arange(samples) / samples
    periodic = signals - slope[:, None] * t[None, :]
    coef = np.fft.rfft(periodic, axis=1) / samples
    coef[:, 1:] *= 2.0
    n_h = samples // 8  # 32 harmonics: the four-bar motion is smooth (checked in tests)
    coef = coef[:, :n_h]

    spec = FourierSpec(omega, coef, slope)
    return leg_params, spec, mean_parts


def _leg_revolution(geom, a_pt, lam, r_r, omega, samples):
    """Leg body parameters, rear-frame signals (18 x samples) over one revolution, the
    revolution-averaged (mass, com, central inertia) of each body in the benchmark frame, and the
    same at ``t = 0`` (crank horizontal, right foot forward)."""
    half = geom.hip_width_m / 2.0
    lateral = {"crank": half / 2.0, "shank": half, "thigh": half}
    masses = legs.segment_masses_kg(geom)
    lengths = legs.segment_lengths_m(geom)
    t = 2 * np.pi / omega * np.arange(samples) / samples
    leg_params: dict[str, float] = {}
    rows = []  # per body: x_frame, z_frame, th_frame over one revolution
    mean_parts, frozen_parts = [], []
    for name in _model.LEG_BODIES:
        seg, side = name.split("_")
        motion = legs.leg_motion(geom, omega, t, left=side == "l")
        xz = motion.segment_com[seg] + a_pt[[0, 2]]
        th = motion.pitch_rad[seg]
        # benchmark (x, z) -> rear frame (Moore): rotate by lam about y, origin rear wheel centre
        dx, dz = xz[:, 0], xz[:, 1] + r_r
        xf = dx * np.cos(lam) - dz * np.sin(lam)
        zf = dx * np.sin(lam) + dz * np.cos(lam)
        rows += [xf, zf, np.unwrap(th - lam)]
        y = lateral[seg] * (1 if side == "r" else -1)
        m = masses[seg]
        i_perp = m * lengths[seg] ** 2 / 12.0
        leg_params.update({f"{name}_y": y, f"{name}_m": m, f"{name}_I": i_perp})
        # revolution average in the benchmark frame
        com = np.array([xz[:, 0].mean(), y, xz[:, 1].mean()])
        c2, s2 = np.mean(np.cos(th) ** 2), np.mean(np.sin(th) ** 2)
        cs = np.mean(np.cos(th) * -np.sin(th))
        # rod along e = (cos th, 0, -sin th): I = i_perp (1 - e e^T)
        eet = np.array([[c2, 0, cs], [0, 0, 0], [cs, 0, s2]])
        i_c = i_perp * (np.eye(3) - eet)
        spread = np.zeros((3, 3))
        for k, j in ((0, 0), (2, 2), (0, 2)):
            a_, b_ = (xz[:, 0] if k == 0 else xz[:, 1]), (xz[:, 0] if j == 0 else xz[:, 1])
            spread[k, j] = np.mean((a_ - a_.mean()) * (b_ - b_.mean()))
        spread[2, 0] = spread[0, 2]
        # spread of the COM path adds m (|r|^2 I - r r^T) averaged
        i_c = i_c + m * (np.trace(spread) * np.eye(3) - spread)
        mean_parts.append((m, com, i_c))
        e0 = np.array([np.cos(th[0]), 0.0, -np.sin(th[0])])
        frozen_parts.append((m, np.array([xz[0, 0], y, xz[0, 1]]),
                             i_perp * (np.eye(3) - np.outer(e0, e0))))
    return leg_params, np.array(rows), mean_parts, frozen_parts


def without_legs(model: str, mean_parts) -> dict[str, float]:
    """Body B of :func:`bicycle_rider` with the revolution-averaged leg bodies removed."""
    bench = bicycle_rider(model)
    m, com, inertia = _body_b(bench)
    m_l = sum(p[0] for p in mean_parts)
    com_l = sum(p[0] * p[1] for p in mean_parts) / m_l
    i_l = sum(p[2] + _parallel(p[0], p[1] - com_l) for p in mean_parts)
    m_rest = m - m_l
    com_rest = (m * com - m_l * com_l) / m_rest
    i_rest = inertia - i_l - _parallel(m_l, com_l - com) - _parallel(m_rest, com_rest - com)
    return _set_body_b(bench, m_rest, com_rest, i_rest)


def legs_fixed(model: str) -> dict[str, float]:
    """Benchmark parameters of the NT model: the legs fixed to the frame at crank angle 0.

    Thesis Sec 3.1.1.3: the models are linearised (and NT keeps the legs fixed) with the crank
    horizontal, right foot forward (``theta_A = 0``). Body B = :func:`bicycle_rider` with the
    revolution-averaged leg bodies replaced by the same bodies frozen at ``t = 0``, so that NP's
    time average and NT differ exactly by this choice of leg configuration (evaluation
    points 1a/2a: the simplified mass distribution).
    """
    if model == "benchmark":
        return bicycle_rider(model)
    s = settings()
    geom = legs.leg_geometry(s["models"][model]["legs"], s["assumptions"]["leg_com_model"])
    bench = bicycle_rider(model)
    _, _, mean, frozen = _leg_revolution(geom, bottom_bracket_m(model), bench["lam"],
                                         bench["rR"], 2.0 * np.pi, 256)
    rest = without_legs(model, mean)
    return _set_body_b(rest, *_combine([_body_b(rest)] + list(frozen)))
