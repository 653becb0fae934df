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
from dataclasses import dataclass
from functools import cache

import numpy as np

from .. import legs, params, paths
from . import model as _model

#: Models with a non-linear counterpart here. CF has its own arm loops
#: (:mod:`pedalrepro.nonlinear.arms`); HS is a substitute (rigid-rider body plus a linear
#: correction to Appendix B, :mod:`pedalrepro.nonlinear.substitute`).
NONLINEAR_MODELS: tuple[str, ...] = ("benchmark", "HS", "CF", "HR", "CR")


@cache
def settings() -> dict:
    """``data/parameters/nonlinear_models.yaml`` (read once; do not modify)."""
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
    r_r = thesis_bicycle(bike)["rR"] if bike != "Benchmark" else bicycle_rider(model)["rR"]
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


def seat_tube_unit(model: str) -> np.ndarray:
    """Unit vector down the seat tube (benchmark frame: forward and down), the seat's travel."""
    s = settings()
    lam = legs.leg_geometry(s["models"][model]["legs"],
                            s["assumptions"]["leg_com_model"]).seat_tube_angle_rad
    return np.array([np.cos(lam), 0.0, np.sin(lam)])


def has_arms(model: str) -> bool:
    """True for a model with arm loops (``arms`` in nonlinear_models.yaml: CF)."""
    return model != "benchmark" and bool(settings()["models"][model].get("arms"))


@cache
def thesis_inputs() -> dict:
    """``data/parameters/thesis_inputs.yaml``: the thesis's bicycle, wheel and rider inputs
    (read once; do not modify)."""
    return params.read_yaml(paths.PARAMETERS / "thesis_inputs.yaml")


@cache
def thesis_bicycle(bicycle: str) -> dict[str, float]:
    """Bicycle-only benchmark parameters with the thesis's geometry and wheels.

    BicycleParameters' values (:func:`_bicycleparameters`) with the steer-axis tilt, trail,
    wheelbase, wheel radii and wheel spin inertias the thesis used
    (``data/parameters/thesis_inputs.yaml``: rounded tabulated values, read off Appendix B's
    Whipple identities).
    """
    alone = dict(_bicycleparameters(bicycle, False)[0])
    table = thesis_inputs()["bicycles"]
    if bicycle not in table:
        return alone
    row = table[bicycle]
    for key in ("c", "w", "rR", "IRyy", "rF", "IFyy"):
        if key not in row:
            raise KeyError(f"data/parameters/thesis_inputs.yaml: bicycles.{bicycle}.{key} missing")
        alone[key] = float(row[key])
    alone["lam"] = float(np.deg2rad(row["lam_deg"]))
    return alone


def _moments(part) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, first moment m r, second moment about the origin) of a (m, com, inertia) part."""
    m, com, inertia = part
    return m, m * np.asarray(com, float), inertia + _parallel(m, np.asarray(com, float))


def _from_moments(m: float, first: np.ndarray, second: np.ndarray):
    com = first / m
    return m, com, second - _parallel(m, com)


@cache
def thesis_rider(bicycle: str) -> tuple[float, np.ndarray, np.ndarray]:
    """The thesis's 72 kg rigid rider (mass, COM, central inertia) on ``bicycle``, seat as built.

    Browser: the benchmark-form rider of Moore et al. (2009), BicycleParameters
    ``JasonBrowserBenchmark.txt`` (``rider_jason.yaml``). Other bicycles (ASSUMPTION, see
    ``thesis_inputs.yaml``): that rider plus the change of posture between the two Yeadon
    configurations of BicycleParameters, scaled to the benchmark rider's mass.
    """
    spec = thesis_inputs()["rider"]
    ref = params.read_yaml(paths.PARAMETERS / "rider_jason.yaml")[spec["benchmark_rider"]]
    base = _body_b({k: float(v) for k, v in ref.items()})
    home = spec["benchmark_rider_bicycle"]
    if bicycle == home:
        return base
    yeadon = {}
    for bike in (home, bicycle):
        alone, both = _bicycleparameters(bike, True)
        yeadon[bike] = _moments(_subtract(_body_b(both), [_body_b(alone)]))
    scale = base[0] / yeadon[home][0]
    m, first, second = _moments(base)
    first = first + scale * (yeadon[bicycle][1] - yeadon[home][1])
    second = second + scale * (yeadon[bicycle][2] - yeadon[home][2])
    return _from_moments(m, first, second)


def _frame(p: dict, body: str) -> tuple[float, np.ndarray, np.ndarray]:
    return p[f"m{body}"], np.array([p[f"x{body}"], 0.0, p[f"z{body}"]]), _inertia(p, body)


def _set_body(p: dict, body: str, part) -> dict:
    m, com, inertia = part
    out = dict(p)
    out.update({f"m{body}": m, f"x{body}": com[0], f"z{body}": com[2],
                f"I{body}xx": inertia[0, 0], f"I{body}yy": inertia[1, 1],
                f"I{body}zz": inertia[2, 2], f"I{body}xz": inertia[0, 2]})
    return out


@dataclass(frozen=True)
class Assembly:
    """A model before calibration: the bicycle and what is rigidly attached to its frames.

    ``bicycle``: bicycle-only benchmark parameters (thesis geometry and wheels; frames B and H
    as measured); ``rear_parts``: rider (without moving arms), legs and cranks frozen at crank
    angle 0, shoulder particles; ``front_parts``: hands and grip particles (CF); ``frozen``:
    the six leg and crank bodies at crank angle 0 (removed again for NP); ``loop``: the arm
    loop or None.
    """

    bicycle: dict
    rear_parts: tuple
    front_parts: tuple
    frozen: tuple
    loop: object = None


@cache
def assembly(model: str, original_seat: bool = False, rider_shift_m: float = 0.0,
             design=None) -> Assembly:
    """The uncalibrated parts of ``model`` (see :class:`Assembly`), thesis Sec 3.1.1.3.

    Rider: :func:`thesis_rider` (72 kg), lowered 0.05 m along the seat tube on the city
    bicycle unless ``original_seat`` (Sec 2.1.1); its legs are taken out with their
    revolution-averaged mass distribution (the rider file's legs are in no particular crank
    position) and the six leg and crank bodies (0.2 kg cranks, Table D.1) are added frozen at
    crank angle 0 (crank horizontal, right foot forward), the configuration the thesis
    linearised. CF: the arm segments are taken out of the rider and replaced by the arm loops.
    ``rider_shift_m``: the rider (without legs) moved further down the seat tube (the Stratos
    rider's seat position is a calibration unknown, ``thesis_inputs.yaml``).
    """
    s = settings()
    if model not in s["models"] or model == "benchmark":
        raise KeyError(f"no non-linear model {model!r}: expected one of {NONLINEAR_MODELS[1:]}")
    spec = s["models"][model]
    a = s["assumptions"]
    bike = thesis_bicycle(spec["bicycle"])
    drop = rider_drop_m(model, original_seat) + rider_shift_m * seat_tube_unit(model)
    rider = thesis_rider(spec["bicycle"])
    rider = (rider[0], rider[1] + drop, rider[2])
    geom = legs.leg_geometry(spec["legs"], a["leg_com_model"])
    _, _, mean, frozen = _leg_revolution(geom, bottom_bracket_m(model), bike["lam"], bike["rR"],
                                         2 * np.pi, 256)
    rider_legs = [p for name, p in zip(_model.LEG_BODIES, mean, strict=True)
                  if not name.startswith("crank")]
    rider = _subtract(rider, [(m, c + drop, i) for m, c, i in rider_legs])
    rear: list = [rider]
    if a["add_cranks"]:
        rear += list(frozen)
    else:
        rear += [p for name, p in zip(_model.LEG_BODIES, frozen, strict=True)
                 if not name.startswith("crank")]
    front: list = []
    loop = None
    if has_arms(model):
        from . import arm_design
        from . import arms as _arms

        rider_mass = thesis_rider(spec["bicycle"])[0]
        if design is None:
            design = arm_design.nominal_design(spec["bicycle"], rider_mass)
        rear[0] = _subtract(rear[0], arm_design.removed_segments(spec["bicycle"], rider_mass,
                                                                   drop))
        loop = arm_design.loop(design, spec["bicycle"], drop)
        at_shoulder, at_grip = _arms.fixed_parts(loop)
        front += arm_design.hands(design, spec["bicycle"])
        front += [p.as_tuple() for p in at_grip]
        rear += [p.as_tuple() for p in at_shoulder]
    return Assembly(bike, tuple(rear), tuple(front), tuple(frozen), loop)


def assemble(asm: Assembly, frames: dict | None = None) -> dict[str, float]:
    """Benchmark parameters of an assembly with the frames ``frames`` (default: measured).

    ``frames``: ``{"B": part, "H": part}`` (mass, COM, central inertia of the bicycle's rear
    and front frame); body B = rear frame + ``rear_parts``, body H = front frame +
    ``front_parts``.
    """
    bike = asm.bicycle
    frames = frames or {}
    rear = frames.get("B", _frame(bike, "B"))
    front = frames.get("H", _frame(bike, "H"))
    out = _set_body(bike, "B", _combine([rear, *asm.rear_parts]))
    if asm.front_parts:
        front = _combine([front, *asm.front_parts])
    return _set_body(out, "H", front)


def clear_caches() -> None:
    """Forget the cached model bodies (after :func:`calibration.use_file`)."""
    for fn in (bicycle_rider, model_bodies, arm_loop):
        fn.cache_clear()


def calibration_of(model: str):
    """The :class:`calibration.Calibration` a model uses; a substitute (HS) that of its body."""
    spec = settings()["models"][model]
    body = spec.get("substitute", {}).get("body_of", model)
    from . import calibration

    return calibration.calibrate(body)


def model_assembly(model: str, original_seat: bool = False, calibrated: bool = True):
    """(assembly, frames) of a model: calibrated (default) or as measured (frames None)."""
    if not calibrated:
        return assembly(model, original_seat), None
    cal = calibration_of(model)
    return assembly(model, original_seat, cal.rider_shift_m, cal.arm_design), cal.frames


def _bicycle_rider(model: str, original_seat: bool, arms: bool, calibrated: bool = True):
    """Benchmark parameters (legs frozen at crank angle 0) and the arm loop of a model."""
    asm, frames = model_assembly(model, original_seat, calibrated)
    return assemble(asm, frames), asm.loop


@cache
def bicycle_rider(model: str, original_seat: bool = False,
                  calibrated: bool = True) -> dict[str, float]:
    """Benchmark parameters of a model with the rider, legs and cranks lumped into body B.

    ``"benchmark"``: Meijaard et al. (2007) unchanged. Otherwise :func:`assemble` of
    :func:`assembly` with the frames calibrated to Appendix B
    (:mod:`pedalrepro.nonlinear.calibration`) unless ``calibrated`` is False: the legs and
    cranks frozen at crank angle 0 (Sec 3.1.1.3), the city rider lowered 0.05 m unless
    ``original_seat`` (Fig E.1). With arms (CF) body B holds the shoulder particles and body H
    the hands and grip particles (:func:`model_bodies`).
    """
    if model == "benchmark":
        return params.benchmark_parameters("benchmark")
    return _bicycle_rider(model, original_seat, has_arms(model), calibrated)[0]


@cache
def model_bodies(model: str, original_seat: bool = False,
                 calibrated: bool = True) -> tuple[dict[str, float], dict]:
    """Benchmark parameters of the model's rigid bodies and the values of its arm symbols.

    Without arms: :func:`bicycle_rider` and ``{}``. With arms (CF,
    :mod:`pedalrepro.nonlinear.arms`): body B without the arms (shoulder particles added),
    the front frame with the hands and the grip particles, and the ``arm_*`` values
    (:data:`model.ARM_PARAMETERS`) of the arm loop at this seat height.
    """
    bench = bicycle_rider(model, original_seat, calibrated)
    if not has_arms(model):
        return bench, {}
    from . import arms as _arms
    from .numeric import moore_parameters

    return bench, _arms.symbol_values(arm_loop(model, original_seat), bench,
                                      moore_parameters(bench))


@cache
def arm_loop(model: str, original_seat: bool = False):
    """The :class:`pedalrepro.nonlinear.arms.ArmLoop` of a model with arms."""
    if not has_arms(model):
        raise ValueError(f"{model} has no arm loops")
    return model_assembly(model, original_seat)[0].loop


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
    (leg_params, spec, frozen_parts)
        ``leg_params``: ``<body>_y``, ``<body>_m``, ``<body>_I`` for :data:`model.LEG_BODIES`;
        ``spec``: ``t -> s`` (positions, rates, accelerations in the generated ``SPEC`` order,
        from a Fourier series of one revolution, ``samples`` per revolution, exact to rounding
        for the band-limited four-bar motion); ``frozen_parts``: the (mass, com, inertia) of each
        body at crank angle 0 in the benchmark frame, the bodies NP removes from body B.
    """
    s = settings()
    geom = legs.leg_geometry(s["models"][model]["legs"], s["assumptions"]["leg_com_model"])
    bench = bicycle_rider(model)
    omega = float(cadence_rad_s)
    leg_params, signals, _, frozen_parts = _leg_revolution(
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
    return leg_params, spec, frozen_parts


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


def without_legs(model: str, original_seat: bool = False) -> dict[str, float]:
    """Body B of :func:`model_bodies` without the six leg and crank bodies frozen at crank angle 0.

    Method NP (Sec 3.1.1.3, issue: the calibrated body is the one with the legs frozen at
    crank angle 0): exactly those bodies are removed and the moving ones are added
    (:func:`leg_bodies`).
    """
    bench = model_bodies(model, original_seat)[0]
    frozen = list(assembly(model, original_seat).frozen)
    return _set_body_b(bench, *_subtract(_body_b(bench), frozen))


def legs_fixed(model: str, original_seat: bool = False) -> dict[str, float]:
    """Benchmark parameters of the NT model: the legs fixed to the frame at crank angle 0.

    Thesis Sec 3.1.1.3: the models are linearised (and NT keeps the legs fixed) with the crank
    horizontal, right foot forward (``theta_A = 0``): :func:`model_bodies`, whose body B holds
    the six leg and crank bodies frozen at ``t = 0`` and whose frames are calibrated to
    Appendix B (:mod:`pedalrepro.nonlinear.calibration`).
    """
    return model_bodies(model, original_seat)[0]
