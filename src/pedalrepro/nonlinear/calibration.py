"""Calibration of the non-linear models' bicycle frames to thesis Appendix B (Sec 3.1.1.3).

The thesis verified its SPACAR models against A. L. Schwab's linearised matrices (relative
1e-13) and printed them as Appendix B. Appendix B's HR and CR are exact Whipple models
(Meijaard et al. 2007) built on rounded geometry and wheel data
(``data/parameters/thesis_inputs.yaml``); with those inputs, the linearisation fixes seven
combinations of the twelve rear- and front-frame unknowns (mass, COM x and z, Ixx, Izz, Ixz of
B and H): a five-parameter family of exact solutions. This module picks the member nearest the
measured frames:

    minimise   sum_k ((p_k - p0_k) / s_k)^2 over the 12 frame parameters p_k (nominal p0_k:
               the measured frames), s_k = ``|p0_k|`` (masses, COM coordinates, moments of
               inertia), s_k = sqrt(Ixx0 Izz0) (products of inertia),
    subject to the 16 entries of the linearisation (legs fixed at crank angle 0) = Appendix B,
               masses > min_mass_kg, central inertias positive definite and satisfying the
               triangle inequalities, COMs inside the box ``com_box`` of thesis_inputs.yaml.

The linearisation is linear in the mass distribution for fixed geometry, so it is the
closed-form Whipple matrices of the assembled benchmark parameters
(``dtk.bicycle.benchmark_par_to_canonical``) plus, for a model with arm loops, the constant
contribution of the moving arm particles (the non-linear model's numerical linearisation minus
the closed form of the same bodies). The solve (SLSQP, then Newton steps on the equalities) is
checked with the non-linear model's own numerical linearisation
(:func:`pedalrepro.nonlinear.nonlinear_model.benchmark_matrices`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from functools import cache

import numpy as np

from .. import params
from . import assembly as asmb
from .rigid import RigidPart, body_part
from .settings import has_arms, model_options, model_spec, thesis_inputs

__all__ = [
    "NAMES", "FRAME_KEYS", "FREE_ENTRIES", "whipple_matrices", "max_relative_difference",
    "frame_vector", "frame_part", "scales", "nearest_valid_iyy", "validity", "Calibration",
    "moments", "from_moments", "Solution", "solve", "steer_stiffness_term", "arm_term",
    "static_stiffness", "arm_half_widths", "elbow_flexion_rad", "particle_arm_term",
    "arm_closure_margin_m2", "calibrate_arms", "to_dict", "from_dict", "save", "use_file",
    "forget_files", "calibrate", "solve_model",
]

#: Matrices of the linearised roll-steer equations (Eq 3.1).
NAMES: tuple[str, ...] = ("M", "C1", "K0", "K2")
#: Calibrated quantities of each frame (benchmark frame; IByy/IHyy do not enter Eq 3.1).
FRAME_KEYS: tuple[str, ...] = ("m", "x", "z", "Ixx", "Izz", "Ixz")
#: Entries that a Whipple model's frames can change independently (Meijaard et al. 2007,
#: Appendix A); the other nine follow from geometry and wheels (identities).
FREE_ENTRIES: tuple[tuple[str, int, int], ...] = (
    ("M", 0, 0), ("M", 0, 1), ("M", 1, 1), ("C1", 0, 1), ("C1", 1, 1), ("K0", 0, 0),
    ("K0", 0, 1))


def whipple_matrices(bench: dict[str, float]) -> dict[str, np.ndarray]:
    """Closed-form ``M, C1, K0, K2`` of the Whipple model (Meijaard et al. 2007, Appendix A)."""
    from dtk.bicycle import benchmark_par_to_canonical

    m, c1, k0, k2 = benchmark_par_to_canonical(dict(bench))
    return {"M": np.asarray(m, float), "C1": np.asarray(c1, float), "K0": np.asarray(k0, float),
            "K2": np.asarray(k2, float)}


def max_relative_difference(mats: dict, target: params.LinearModel) -> float:
    """Largest ``|a - b|`` over the 16 entries, each scaled by its matrix's largest ``|b|``."""
    return float(max(np.max(np.abs(np.asarray(mats[k]) - getattr(target, k)))
                     / np.max(np.abs(getattr(target, k))) for k in NAMES))


def frame_vector(part: RigidPart) -> np.ndarray:
    """``(m, x, z, Ixx, Izz, Ixz)`` of a frame."""
    i = part.inertia
    return np.array([part.mass, part.com[0], part.com[2], i[0, 0], i[2, 2], i[0, 2]])


def frame_part(v: np.ndarray, i_yy: float) -> RigidPart:
    """The frame with ``(m, x, z, Ixx, Izz, Ixz)`` and ``Iyy``."""
    inertia = np.array([[v[3], 0.0, v[5]], [0.0, i_yy, 0.0], [v[5], 0.0, v[4]]])
    return RigidPart(float(v[0]), np.array([v[1], 0.0, v[2]]), inertia)


def scales(v0: np.ndarray) -> np.ndarray:
    s = np.abs(v0).astype(float)
    s[5] = np.sqrt(v0[3] * v0[4])
    return s


def nearest_valid_iyy(v: np.ndarray, i_yy: float) -> float:
    """The pitch moment nearest ``i_yy`` that satisfies the triangle inequalities with the
    frame's principal moments in its plane of symmetry (``|p1 - p2| <= Iyy <= p1 + p2``)."""
    ixx, izz, ixz = v[3], v[4], v[5]
    spread = float(np.sqrt((ixx - izz) ** 2 + 4 * ixz**2))
    return float(np.clip(i_yy, spread, ixx + izz))


def validity(v: np.ndarray, i_yy: float, box: dict, min_mass: float,
             free_iyy: bool = False) -> np.ndarray:
    """Inequalities (>= 0) of a physically valid frame: mass, inertia, COM on the bicycle.
    ``free_iyy``: Iyy is :func:`nearest_valid_iyy` (the triangle inequalities then hold)."""
    m, x, z, ixx, izz, ixz = v
    if free_iyy:
        i_yy = nearest_valid_iyy(v, i_yy)
    return np.array([
        m - min_mass,
        ixx, izz, ixx * izz - ixz**2,            # positive definite (with Iyy > 0)
        ixx + izz - i_yy,                         # triangle inequalities of the principal
        i_yy**2 - (ixx - izz) ** 2 - 4 * ixz**2,  # moments (p1 + p2 >= Iyy, |p1 - p2| <= Iyy)
        x - box["x"][0], box["x"][1] - x, z - box["z"][0], box["z"][1] - z])


@dataclass
class Calibration:
    """Result of :func:`calibrate` for one model.

    ``nominal``/``frames``: ``{"B": part, "H": part}`` before and after (mass, COM, central
    inertia of the bicycle's rear and front frame); ``distance``: the metric's value;
    ``residual``: largest relative difference of the closed-form linearisation from Appendix
    B; ``valid``: every inequality holds.
    """

    model: str
    nominal: dict
    frames: dict
    distance: float
    residual: float
    valid: bool
    arm_contribution: dict = field(default_factory=dict)
    rider_shift_m: float = 0.0
    frames_only: Solution | None = None
    arm_design: object = None
    arm_nominal: object = None

    def rows(self) -> list[tuple]:
        """(model, body, parameter, uncalibrated, calibrated) rows for the table."""
        out = []
        for body, label in (("B", "rear frame"), ("H", "front frame")):
            before, after = frame_vector(self.nominal[body]), frame_vector(self.frames[body])
            for key, b, a in zip(FRAME_KEYS, before, after, strict=True):
                out.append((self.model, label, key, float(b), float(a)))
            i_before, i_after = (float(p[body].inertia[1, 1]) for p in (self.nominal,
                                                                          self.frames))
            if i_after != i_before:  # free_pitch_inertia (thesis_inputs.yaml)
                out.append((self.model, label, "Iyy", i_before, i_after))
        return out


def _arm_contribution(model: str, asm, frames) -> dict[str, np.ndarray]:
    """Linearisation of the moving arm particles (zero without arms): numeric - closed form."""
    if asm.loop is None:
        return {k: np.zeros((2, 2)) for k in NAMES}
    from . import arms as _arms
    from .nonlinear_model import NonlinearModel, benchmark_matrices, moore_parameters

    bench = asmb.assemble(asm, frames)
    values = _arms.symbol_values(asm.loop, bench, moore_parameters(bench))
    full = benchmark_matrices(NonlinearModel(bench, model_options(model),
                                             arm_parameters=values))
    closed = whipple_matrices(bench)
    return {k: full[k] - closed[k] for k in NAMES}


def moments(v: np.ndarray) -> np.ndarray:
    """Mass moments ``(m, m x, m z, Jxx, Jzz, Jxz)`` of a frame (second moments about the rear
    contact point, tensor convention) from ``(m, x, z, Ixx, Izz, Ixz)``; the linearisation is
    affine in them (fixed geometry and wheels)."""
    m, x, z, ixx, izz, ixz = v
    return np.array([m, m * x, m * z, ixx + m * z**2, izz + m * x**2, ixz - m * x * z])


def from_moments(mu: np.ndarray) -> np.ndarray:
    """Inverse of :func:`moments`."""
    m = mu[0]
    x, z = mu[1] / m, mu[2] / m
    return np.array([m, x, z, mu[3] - m * z**2, mu[4] - m * x**2, mu[5] + m * x * z])


@dataclass
class Solution:
    """Frames of :func:`solve`, the metric's value, the closed-form residual, validity."""

    frames: dict
    distance: float
    residual: float
    valid: bool


def solve(asm, target: params.LinearModel, settings: dict,
          extra: dict[str, np.ndarray] | None = None, starts: int = 12,
          free_iyy: bool = False) -> Solution:
    """Frames nearest the assembly's measured frames whose linearisation is ``target``.

    The seven free entries are affine in the frames' mass moments (:func:`moments`), so their
    solution set is an affine subspace ``mu = mu_p + N z`` (``N``: null space, 5 columns); the
    metric (module docstring) is minimised over ``z`` under the validity inequalities (SLSQP from
    ``starts`` starting points, the best valid one kept). ``extra``: a constant contribution
    added to the closed-form matrices (moving arm particles). ``free_iyy``: the frames' pitch
    moments IByy, IHyy (absent from the linearisation) take the value nearest the measured one
    that keeps the inertia physically valid (:func:`nearest_valid_iyy`).
    """
    from scipy.linalg import null_space
    from scipy.optimize import minimize

    extra = extra or {k: np.zeros((2, 2)) for k in NAMES}
    bike = asm.bicycle
    v0 = np.concatenate([frame_vector(body_part(bike, b)) for b in ("B", "H")])
    mu0 = np.concatenate([moments(v0[:6]), moments(v0[6:])])
    iyy = {"B": bike["IByy"], "H": bike["IHyy"]}
    scale = {k: float(np.max(np.abs(getattr(target, k)))) for k in NAMES}
    box = settings["com_box"]
    min_mass = float(settings["min_mass_kg"])

    def frame_of(mu6, body):
        v = from_moments(mu6)
        return frame_part(v, nearest_valid_iyy(v, iyy[body]) if free_iyy else iyy[body])

    def frames_of_mu(mu):
        return {"B": frame_of(mu[:6], "B"), "H": frame_of(mu[6:], "H")}

    def mats(mu):
        m = whipple_matrices(asmb.assemble(asm, frames_of_mu(mu)))
        return {k: m[k] + extra[k] for k in NAMES}

    def free(mu):
        m = mats(mu)
        return np.array([(m[k][i, j] - getattr(target, k)[i, j]) / scale[k]
                         for k, i, j in FREE_ENTRIES])

    # affine map: exact coefficients from unit steps (round-off only)
    r0 = free(mu0)
    step = np.maximum(np.abs(mu0), 1.0)
    a = np.column_stack([(free(mu0 + h * e) - r0) / h for h, e in zip(step, np.eye(12),
                                                                       strict=True)])
    mu_p = mu0 - np.linalg.lstsq(a, r0, rcond=None)[0]
    n = null_space(a)

    norm = np.concatenate([scales(v0[:6]), scales(v0[6:])])

    def distance(z):
        mu = mu_p + n @ z
        if mu[0] <= 0 or mu[6] <= 0:
            return 1e6
        d = (np.concatenate([from_moments(mu[:6]), from_moments(mu[6:])]) - v0) / norm
        return float(d @ d)

    def ineq(z):
        mu = mu_p + n @ z
        if mu[0] <= 0 or mu[6] <= 0:
            return np.full(20, -1.0)
        return np.concatenate([
            validity(from_moments(mu[:6]), iyy["B"], box["rear"], min_mass, free_iyy),
            validity(from_moments(mu[6:]), iyy["H"], box["front"], min_mass, free_iyy)])

    z_back = np.linalg.lstsq(n, mu0 - mu_p, rcond=None)[0]  # nearest to the measured frames
    rng = np.random.default_rng(0)
    best = None
    for k in range(starts):
        z_start = z_back + (0 if k == 0 else rng.normal(scale=np.linalg.norm(mu0) * 0.02,
                                                        size=n.shape[1]))
        res = minimize(distance, z_start, method="SLSQP",
                       constraints=[{"type": "ineq", "fun": ineq}],
                       options={"ftol": 1e-14, "maxiter": 500})
        ok = bool(np.all(ineq(res.x) >= -1e-10))
        key = (not ok, distance(res.x))
        if best is None or key < best[0]:
            best = (key, res.x)
    mu = mu_p + n @ best[1]
    # Newton steps on the free entries (minimum norm) to round-off
    for _ in range(4):
        r = free(mu)
        if np.max(np.abs(r)) < 1e-15:
            break
        mu = mu - np.linalg.pinv(a, rcond=1e-12) @ r
    residual = max_relative_difference(mats(mu), target)
    return Solution(frames_of_mu(mu), distance(best[1]), residual, not best[0][0])


def steer_stiffness_term(mats: dict, lam_rad: float) -> float:
    """``dK0[1,1] = K0[1,1] - K0[0,1] sin(lam)``: zero for every Whipple model (Meijaard et al.
    2007: K0[1,1] = -S_A sin(lam), K0[0,1] = -S_A); the arm loops' signature."""
    return float(mats["K0"][1, 1] - mats["K0"][0, 1] * np.sin(lam_rad))


def arm_term(model: str, design, rider_shift_m: float = 0.0) -> float:
    """dK0[1,1] of ``model`` built with the arm design ``design`` (numerical linearisation;
    independent of the frames, which satisfy the Whipple identity), the rider moved
    ``rider_shift_m`` down the seat tube."""
    from . import arms as _arms
    from .nonlinear_model import NonlinearModel, moore_parameters

    asm = asmb.assembly(model, False, float(rider_shift_m), design)
    bench = asmb.assemble(asm)
    values = _arms.symbol_values(asm.loop, bench, moore_parameters(bench))
    nl = NonlinearModel(bench, model_options(model), arm_parameters=values)
    return steer_stiffness_term({"K0": static_stiffness(nl)}, bench["lam"])


def static_stiffness(nl) -> np.ndarray:
    """``K0`` of a non-linear model from one complex-step Jacobian at zero speed (the static
    part of :func:`.nonlinear_model.benchmark_matrices`: ``g K0 = -M dq''/dq`` at ``v = 0``)."""
    h = 1e-30
    x0 = nl.upright_state(0.0).astype(complex)
    cols = []
    for k in (0, 2):  # roll, steer
        dx = x0.copy()
        dx[k] += 1j * h
        cols.append(nl._complex_rhs(dx, (0.0, 0.0)).imag[[3, 5]] / h)
    binv = []
    for k in range(2):
        tq = [0.0, 0.0]
        tq[k] = 1j * h
        binv.append(nl._complex_rhs(x0, tuple(tq)).imag[[3, 5]] / h)
    m = np.linalg.inv(np.column_stack(binv))
    return -m @ np.column_stack(cols) / nl.bench["g"]


def arm_half_widths(design, ranges: dict) -> np.ndarray:
    """Half-widths of the plausible ranges of the design's parameters (thesis_inputs.yaml)."""
    out = []
    for key, value in zip(design.keys(), design.vector(), strict=True):
        if key not in ranges:
            raise KeyError(f"data/parameters/thesis_inputs.yaml: calibration.arm_ranges.{key} "
                           "missing")
        r = ranges[key]
        out.append(float(r["abs"]) if "abs" in r else float(r["rel"]) * abs(value))
    return np.array(out)


def _yeadon_elbow_flexion_rad(bicycle: str) -> float:
    """Elbow flexion of BicycleParameters' Yeadon rider with the hands on the grips (original
    seat): the least flexion the calibrated CF arms keep at the original seat."""
    from . import arms as _arms

    y = _arms.yeadon_arms(bicycle)
    u, w = y.elbow - y.shoulder, y.grip - y.elbow
    return float(np.arccos(u @ w / np.linalg.norm(u) / np.linalg.norm(w)))


def elbow_flexion_rad(design, model: str, original_seat: bool) -> float:
    """Elbow flexion (0: straight arm) of the design's loop at steer 0 at a seat height; NaN
    when the arm cannot reach the grip."""
    drop = asmb.rider_drop_m(model, original_seat)
    s = np.array([design.shoulder_x, design.shoulder_y, design.shoulder_z]) + drop
    d = float(np.linalg.norm(design.grip() - s))
    cos_in = (design.a**2 + design.b**2 - d**2) / (2 * design.a * design.b)
    return float(np.pi - np.arccos(cos_in)) if abs(cos_in) <= 1 else float("nan")


def _arm_loop(model: str, design, rider_shift_m: float):
    """The right arm loop of ``design`` with the rider moved ``rider_shift_m`` down the seat
    tube (as :func:`.assembly.assembly` places it)."""
    from .arm_design import loop

    bicycle = model_spec(model)["bicycle"]
    drop = asmb.rider_drop_m(model) + rider_shift_m * asmb.seat_tube_unit(model)
    return loop(design, bicycle, drop)


def particle_arm_term(model: str, design, rider_shift_m: float = 0.0) -> float:
    """dK0[1,1] of the design's moving arm particles alone
    (:func:`pedalrepro.nonlinear.arm_design.particle_steer_term`, central differences: within
    ~1e-9 of :func:`arm_term` at a 400th of its cost): the search's term; :func:`arm_term`
    polishes the result."""
    from . import arms as _arms
    from .arm_design import particle_steer_term

    bench = asmb.thesis_bicycle(model_spec(model)["bicycle"])
    arm = _arm_loop(model, design, rider_shift_m)
    return particle_steer_term(lambda d: _arms.moving_particles(arm, d, bench), bench["lam"])


def arm_closure_margin_m2(model: str, design, steer_rad: float,
                          rider_shift_m: float = 0.0) -> float:
    """:func:`pedalrepro.nonlinear.arms.closure_margin_m2` of the design's loops (-1 when they
    do not close at zero steer)."""
    from . import arms as _arms

    try:
        arm = _arm_loop(model, design, rider_shift_m)
    except ValueError:
        return -1.0
    return _arms.closure_margin_m2(arm, steer_rad,
                                   asmb.thesis_bicycle(model_spec(model)["bicycle"]))


def calibrate_arms(model: str, nominal, target_term: float, ranges: dict,
                   min_flexion_original_rad: float = 0.0, min_steer_reach_rad: float = 0.0,
                   rider_shift_m: float = 0.0, starts=None):
    """Smallest change of the arm design (in units of the range half-widths) giving
    ``dK0[1,1] = target_term``, with the arms still reaching the grips at the original seat
    height with an elbow flexion of at least ``min_flexion_original_rad`` (Fig E.1 needs the
    model there) and, while steering, up to ``min_steer_reach_rad`` (the loop must close over
    the steer angles the simulations reach). SLSQP from each of ``starts`` (normalised
    changes; default the nominal design), the smallest feasible result kept; ``dK0`` of the
    arm particles (:func:`particle_arm_term`), then Newton steps on the non-linear model's
    numerical linearisation (:func:`arm_term`).

    Returns (design, normalised change per parameter).
    """
    from scipy.optimize import minimize

    r = arm_half_widths(nominal, ranges)
    v0 = nominal.vector()

    def design(z):
        return nominal.with_vector(v0 + r * z)

    def term(z, fn=particle_arm_term):
        try:
            with np.errstate(invalid="ignore"):  # NaN elbow: the loop is open while steering
                value = fn(model, design(z), rider_shift_m) - target_term
        except ValueError:  # the loop does not close
            return 1e3
        return value if np.isfinite(value) else 1e3

    def term_jac(z, fn=particle_arm_term, step=1e-5):
        f = term(z, fn)
        return np.array([(term(z + step * e, fn) - f) / step for e in np.eye(v0.size)])

    def model_term(z):
        return term(z, arm_term)

    def reach(z):
        flex = elbow_flexion_rad(design(z), model, True)
        return (flex if np.isfinite(flex) else -1.0) - min_flexion_original_rad

    constraints = [{"type": "eq", "fun": term, "jac": term_jac},
                   {"type": "ineq", "fun": reach}]
    if min_steer_reach_rad > 0:
        constraints.append({"type": "ineq", "fun": lambda z: arm_closure_margin_m2(
            model, design(z), min_steer_reach_rad, rider_shift_m)})
    best = None
    for z0 in (np.zeros(v0.size),) if starts is None else starts:
        res = minimize(lambda z: float(z @ z), np.asarray(z0, float), jac=lambda z: 2 * z,
                       method="SLSQP", constraints=constraints,
                       options={"ftol": 1e-16, "maxiter": 200})
        z = res.x
        for _ in range(8):  # Newton on the model's equation along its gradient (keeps the
            f = model_term(z)  # optimum; the particle term's round-off is ~1e-9)
            if abs(f) < 1e-13:
                break
            g = term_jac(z, arm_term, 1e-6)
            z = z - g * f / float(g @ g)
        ok = abs(model_term(z)) < 1e-9 and all(np.all(np.asarray(c["fun"](z)) >= -1e-9)
                                          for c in constraints[1:])
        key = (not ok, float(z @ z))
        if best is None or key < best[0]:
            best = (key, z)
    return design(best[1]), best[1]


def _arm_starts(nominal) -> list[np.ndarray] | None:
    """Starting points of :func:`calibrate_arms` for a design with a free arm plane (HS): the
    nominal straight arm is singular (its dK0[1,1] diverges at full extension), so the search
    starts from flexed arms (segments +1 half-width) with the elbow turned by 0, +-1/2 and +-1
    half-widths of its direction."""
    if nominal.elbow_dir_rad is None:
        return None
    keys = nominal.keys()
    out = []
    for turn in (0.0, 0.5, -0.5, 1.0, -1.0):
        z = np.zeros(len(keys))
        z[keys.index("a")] = z[keys.index("b")] = 1.0
        z[keys.index("elbow_dir_rad")] = turn
        out.append(z)
    return out


#: Calibrations read by :func:`use_file` (the pipeline's downstream rules), by model.
_FROM_FILE: dict[str, Calibration] = {}


def _part_dict(part: RigidPart) -> dict[str, float]:
    m, com, i = part.mass, part.com, part.inertia
    return {"m": float(m), "x": float(com[0]), "z": float(com[2]), "Ixx": float(i[0, 0]),
            "Iyy": float(i[1, 1]), "Izz": float(i[2, 2]), "Ixz": float(i[0, 2])}


def _dict_part(d: dict):
    return frame_part(np.array([d[k] for k in FRAME_KEYS], float), float(d["Iyy"]))


def to_dict(cal: Calibration) -> dict:
    """A YAML-ready record of a calibration (floats at full precision)."""
    out = {"frames": {b: _part_dict(p) for b, p in cal.frames.items()},
           "nominal": {b: _part_dict(p) for b, p in cal.nominal.items()},
           "distance": float(cal.distance), "residual": float(cal.residual),
           "valid": bool(cal.valid), "rider_shift_m": float(cal.rider_shift_m),
           "arm_contribution": {k: np.asarray(v, float).tolist()
                                for k, v in cal.arm_contribution.items()}}
    for key, design in (("arm_design", cal.arm_design), ("arm_nominal", cal.arm_nominal)):
        if design is not None:
            out[key] = {f.name: None if getattr(design, f.name) is None
                        else float(getattr(design, f.name)) for f in fields(design)}
    return out


def from_dict(model: str, d: dict) -> Calibration:
    """Inverse of :func:`to_dict`."""
    from .arm_design import ArmDesign

    try:
        designs = {k: ArmDesign(**d[k]) if d.get(k) else None
                   for k in ("arm_design", "arm_nominal")}
        return Calibration(model, {b: _dict_part(p) for b, p in d["nominal"].items()},
                           {b: _dict_part(p) for b, p in d["frames"].items()},
                           float(d["distance"]), float(d["residual"]), bool(d["valid"]),
                           {k: np.array(v, float) for k, v in d["arm_contribution"].items()},
                           float(d["rider_shift_m"]), arm_design=designs["arm_design"],
                           arm_nominal=designs["arm_nominal"])
    except KeyError as err:
        raise KeyError(f"calibration record of {model}: key {err} missing") from err


def save(path, models) -> None:
    """Write the calibrations of ``models`` to a YAML file (rule nonlinear_calibration)."""
    import yaml

    with open(path, "w") as fh:
        yaml.safe_dump({m: to_dict(calibrate(m)) for m in models}, fh, sort_keys=False)


def use_file(path) -> list[str]:
    """Use the calibrations written by :func:`save` (downstream rules: no re-solve).

    Returns the models read. Call it before building any model (or then call
    :func:`.bodies.clear_caches`).
    """
    import yaml

    with open(path) as fh:
        data = yaml.safe_load(fh) or {}
    _FROM_FILE.update({m: from_dict(m, d) for m, d in data.items()})
    return sorted(data)


def forget_files() -> None:
    """Drop the calibrations read by :func:`use_file` (back to solving on demand)."""
    _FROM_FILE.clear()


def calibrate(model: str) -> Calibration:
    """The calibration of ``model``: read by :func:`use_file`, else :func:`solve_model`."""
    if model in _FROM_FILE:
        return _FROM_FILE[model]
    return solve_model(model)


@cache
def solve_model(model: str) -> Calibration:
    """Calibrate ``model``'s rear and front frames to its Appendix B matrices (see module).

    Runs with one BLAS thread (as a one-thread Snakemake job does): the searches over starting
    points and seat shift pick the best of several local optima of a shallow metric, and
    multi-threaded BLAS round-off can change which one wins (HS: metric 9.14 with one thread,
    9.91 with the default threads), so the result must not depend on the caller's threads.

    Where ``thesis_inputs.yaml`` makes the rider's seat position an unknown (``rider_seat_shift``:
    the Stratos, whose rider is an assumption), the metric gains ``(d / scale_m)^2`` for a shift
    ``d`` of the rider down the seat tube, minimised over ``range_m`` (grid, then bounded
    refinement); ``frames_only`` keeps the solution at ``d = 0``.
    """
    import scipy.optimize  # noqa: F401  (loads scipy's own BLAS, so that the limit reaches it)
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):  # every BLAS loaded now: numpy's and scipy's
        return _solve_model(model)


def _solve_model(model: str) -> Calibration:
    """:func:`solve_model` in the caller's threads."""
    settings = thesis_inputs()["calibration"]
    bicycle = model_spec(model)["bicycle"]
    target = params.appendix_b_model(model)

    design = arm_nominal = None
    spec = settings.get("rider_seat_shift", {}).get(bicycle)
    if has_arms(model):
        from .arm_design import nominal_design

        plane = model_spec(model).get("arm_plane", "sagittal")
        arm_nominal = nominal_design(bicycle, asmb.thesis_rider(bicycle).mass, plane)
        lam = asmb.thesis_bicycle(bicycle)["lam"]
        term = steer_stiffness_term({"K0": target.K0}, lam)
        min_flex = _yeadon_elbow_flexion_rad(bicycle) if plane == "sagittal" else 0.0
        min_reach = float(settings.get("arm_min_steer_reach_rad", {}).get(model, 0.0))

        def arms_at(shift: float, starts=None):
            return calibrate_arms(model, arm_nominal, term, settings["arm_ranges"], min_flex,
                                  min_reach, shift, starts or _arm_starts(arm_nominal))

        design, z = arms_at(0.0)

    def at(shift: float, starts: int = 12, design=design) -> tuple[Solution, dict, dict]:
        asm = asmb.assembly(model, False, float(shift), design)
        nominal = {b: body_part(asm.bicycle, b) for b in ("B", "H")}
        extra = _arm_contribution(model, asm, nominal)
        free_iyy = model in settings.get("free_pitch_inertia", ())
        return solve(asm, target, settings, extra, starts, free_iyy), nominal, extra

    base, nominal, extra = at(0.0)
    if not spec:
        return Calibration(model, nominal, base.frames, base.distance, base.residual, base.valid,
                           extra, arm_design=design, arm_nominal=arm_nominal)
    from scipy.optimize import minimize_scalar

    scale = float(spec["scale_m"])
    lo, hi = (float(x) for x in spec["range_m"])

    def total(shift: float, starts: int = 4) -> float:
        try:
            sol = at(shift, starts)[0]
        except ValueError:  # the shoulders moved out of the arms' reach
            return 1e9
        return sol.distance + (shift / scale) ** 2 + (0.0 if sol.valid else 1e6)

    grid = np.linspace(lo, hi, int(spec.get("grid", 21)))
    values = [total(d) for d in grid]
    k = int(np.argmin(values))
    res = minimize_scalar(total, bounds=(grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]),
                          method="bounded", options={"xatol": 1e-5})
    shift = float(res.x)
    if design is not None:
        # the shift moves the shoulders: the arms again, at the shift (from the design at 0)
        design, _ = arms_at(shift, [z])
    sol, _, extra = at(shift, design=design)
    return Calibration(model, nominal, sol.frames, sol.distance + (shift / scale) ** 2,
                       sol.residual, sol.valid, extra, shift, base, design, arm_nominal)
