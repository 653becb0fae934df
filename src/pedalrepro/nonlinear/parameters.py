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

#: Models with a non-linear counterpart here. CF has its own arm loops
#: (:mod:`pedalrepro.nonlinear.arms`); HS is a substitute (rigid-rider body plus a linear
#: correction to Appendix B, :mod:`pedalrepro.nonlinear.substitute`).
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


def _subtract(total: tuple, parts: list) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, com, central inertia) of ``total`` without ``parts`` (inverse of _combine)."""
    m, com, inertia = total
    m_p = sum(p[0] for p in parts)
    m_rest = m - m_p
    com_rest = (m * com - sum(p[0] * p[1] for p in parts)) / m_rest
    about = inertia + _parallel(m, com - com_rest) - sum(
        p[2] + _parallel(p[0], p[1] - com_rest) for p in parts)
    return m_rest, com_rest, about


def rider_drop_m(model: str, original_seat: bool = False) -> np.ndarray:
    """Displacement of the rider (benchmark frame, m) for the lowered city seat (Sec 2.1.1).

    0.05 m down along the seat tube (0.77 -> 0.72 m) on the city bicycle, zero otherwise or
    with ``original_seat`` (Fig E.1).
    """
    s = settings()
    spec = s["models"][model]
    a = s["assumptions"]
    geom = legs.leg_geometry(spec["legs"], a["leg_com_model"])
    if spec["legs"] == "city" and a["lower_city_rider_along_seat_tube"] and not original_seat:
        original = params.legs()["seat_geometry"]["city"]["original_seat_tube_plus_post_m"]
        drop = original - geom.seat_tube_plus_post_m
        lam = geom.seat_tube_angle_rad
        return drop * np.array([np.cos(lam), 0.0, np.sin(lam)])
    return np.zeros(3)


def has_arms(model: str) -> bool:
    """True for a model with arm loops (``arms`` in nonlinear_models.yaml: CF)."""
    return model != "benchmark" and bool(settings()["models"][model].get("arms"))


def _bicycle_rider(model: str, original_seat: bool, arms: bool):
    """Benchmark parameters (and the arm loop, if ``arms``) of a model; see bicycle_rider."""
    s = settings()
    if model not in s["models"]:
        raise KeyError(f"no non-linear model {model!r}: expected one of {NONLINEAR_MODELS}")
    spec = s["models"][model]
    alone, both = _bicycleparameters(spec["bicycle"], spec["rider"])
    a = s["assumptions"]
    frame = _body_b(alone)
    total = _body_b(both)
    # the rider alone = total - bicycle frame (inverse parallel-axis combination)
    rider = _subtract(total, [frame])
    drop = rider_drop_m(model, original_seat)
    loop = None
    front_parts: list = []
    if arms:
        from . import arms as _arms

        yeadon = _arms.yeadon_arms(spec["bicycle"])
        rider = _subtract(rider, [p.as_tuple() for p in yeadon.segments])
        loop = _arms.arm_loop(yeadon.shoulder + drop, yeadon)
        at_shoulder, at_grip = _arms.fixed_parts(loop)
        mirror = np.diag([1.0, -1.0, 1.0])
        hands = [yeadon.hand.as_tuple(), (yeadon.hand.mass, mirror @ yeadon.hand.com,
                                          mirror @ yeadon.hand.inertia @ mirror)]
        front_parts = hands + [p.as_tuple() for p in at_grip]
    parts = [frame, (rider[0], rider[1] + drop, rider[2])]
    if loop is not None:
        parts += [p.as_tuple() for p in at_shoulder]
    out = dict(both)
    if a["add_cranks"]:
        geom = legs.leg_geometry(spec["legs"], a["leg_com_model"])
        bb = s["bottom_bracket"][spec["bicycle"]]
        a_pt = np.array([np.sqrt(bb["lcs"] ** 2 - (both["rR"] - bb["hbb"]) ** 2), 0.0, -bb["hbb"]])
        _, _, mean, _ = _leg_revolution(geom, a_pt, both["lam"], both["rR"], 2 * np.pi, 256)
        parts += [p for name, p in zip(_model.LEG_BODIES, mean, strict=True)
                  if name.startswith("crank")]
    out = _set_body_b(out, *_combine(parts))
    if front_parts:
        h = (out["mH"], np.array([out["xH"], 0.0, out["zH"]]), _inertia(out, "H"))
        m, com, inertia = _combine([h] + front_parts)
        out.update(mH=m, xH=com[0], zH=com[2], IHxx=inertia[0, 0], IHyy=inertia[1, 1],
                   IHzz=inertia[2, 2], IHxz=inertia[0, 2])
    return out, loop


@cache
def bicycle_rider(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of a model with the rider and legs lumped rigidly into body B.

    ``"benchmark"``: Meijaard et al. (2007) unchanged. ``"HR"``/``"CR"`` (and the rigid-rider
    bodies of ``"HS"``/``"CF"``): Stratos/Browser + rider Jason + two 0.2 kg cranks at the
    crank axis; on the city bicycle the rider is lowered 0.05 m along the seat tube
    (0.77 -> 0.72 m, Sec 2.1.1) unless ``original_seat`` (Fig E.1).
    """
    if model == "benchmark":
        return params.benchmark_parameters("benchmark")
    return _bicycle_rider(model, original_seat, False)[0]


@cache
def model_bodies(model: str, original_seat: bool = False) -> tuple[dict[str, float], dict]:
    """Benchmark parameters of the model's rigid bodies and the values of its arm symbols.

    Without arms: :func:`bicycle_rider` and ``{}``. With arms (CF,
    :mod:`pedalrepro.nonlinear.arms`): body B without the arms (shoulder particles added),
    the front frame with the hands and the grip particles, and the ``arm_*`` values
    (:data:`model.ARM_PARAMETERS`) of the arm loop at this seat height.
    """
    if not has_arms(model):
        return bicycle_rider(model, original_seat), {}
    from . import arms as _arms
    from .numeric import moore_parameters

    bench, loop = _bicycle_rider(model, original_seat, True)
    return bench, _arms.symbol_values(loop, bench, moore_parameters(bench))


@cache
def arm_loop(model: str, original_seat: bool = False):
    """The :class:`pedalrepro.nonlinear.arms.ArmLoop` of a model with arms."""
    if not has_arms(model):
        raise ValueError(f"{model} has no arm loops")
    return _bicycle_rider(model, original_seat, True)[1]


def steer_limit_rad(model: str, original_seat: bool = False) -> float:
    """Steer angle at which a run of the model ends like a fall (inf without arm loops).

    With arm loops: :data:`arms.STEER_REACH_FRACTION` of the steer angle at which an arm is
    fully stretched (:func:`arms.steer_reach_rad`).
    """
    if not has_arms(model):
        return float("inf")
    from . import arms as _arms

    bench = model_bodies(model, original_seat)[0]
    return _arms.STEER_REACH_FRACTION * _arms.steer_reach_rad(arm_loop(model, original_seat),
                                                              bench)


def model_options(model: str, legs: bool = False) -> _model.ModelOptions:
    """The symbolic model of ``model`` (arm loops for CF), with or without moving legs."""
    return _model.ModelOptions(legs=legs, arms=has_arms(model))


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


def without_legs(model: str, mean_parts, original_seat: bool = False) -> dict[str, float]:
    """Body B of :func:`model_bodies` with the revolution-averaged leg bodies removed."""
    bench = model_bodies(model, original_seat)[0]
    return _set_body_b(bench, *_subtract(_body_b(bench), list(mean_parts)))


def legs_fixed(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of the NT model: the legs fixed to the frame at crank angle 0.

    Thesis Sec 3.1.1.3: the models are linearised (and NT keeps the legs fixed) with the crank
    horizontal, right foot forward (``theta_A = 0``). Body B = :func:`bicycle_rider` with the
    revolution-averaged leg bodies replaced by the same bodies frozen at ``t = 0``, so that NP's
    time average and NT differ exactly by this choice of leg configuration (evaluation
    points 1a/2a: the simplified mass distribution). With arms (CF) body B and the front frame
    of :func:`model_bodies`; the arm symbols are :func:`model_bodies`' second item.
    """
    if model == "benchmark":
        return bicycle_rider(model)
    s = settings()
    geom = legs.leg_geometry(s["models"][model]["legs"], s["assumptions"]["leg_com_model"])
    bench = model_bodies(model, original_seat)[0]
    _, _, mean, frozen = _leg_revolution(geom, bottom_bracket_m(model), bench["lam"],
                                         bench["rR"], 2.0 * np.pi, 256)
    rest = without_legs(model, mean, original_seat)
    return _set_body_b(rest, *_combine([_body_b(rest)] + list(frozen)))
