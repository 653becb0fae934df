"""Symbolic non-linear Carvallo-Whipple bicycle-rider model (thesis Sec 3.1.1.3, Fig 3.4).

The thesis built its non-linear models in SPACAR; this project derives them with SymBRiM
(``symbrim``, Moore's parametrisation of the Whipple bicycle) and ``sympy.physics.mechanics``
(Kane's method). The rigid part of the rider is lumped into the rear frame (benchmark body B);
the legs and cranks are optional separate bodies whose motion relative to the rear frame is
*prescribed* (specified functions of time, the isokinetic crank of Sec 3.1.1.3), so the model
keeps the Whipple bicycle's three velocity degrees of freedom (roll rate, rear wheel rate,
steer rate). Model CF adds the two arm loops of the city posture as particles whose positions are
explicit (closed-form) functions of the steer angle (:func:`_add_arms`,
:mod:`pedalrepro.nonlinear.arms`): still three degrees of freedom. Kane's equations are formed
with each arm coordinate as a function placeholder of the steer angle, and its closed form and
steer derivatives are put in afterwards (:func:`_function_of_steer`).

Formulation
-----------
Kane's equations are formed for all eight generalised speeds ``u`` of SymBRiM's
``WhippleBicycleMoore`` *without* eliminating the dependent ones symbolically:
``M(q, s) u' = F(q, u, s)`` plus the five velocity constraints ``A(q) u = 0`` (four
no-slip rolling constraints and the time derivative of the holonomic ground-contact constraint
of the front wheel) and their time derivative ``A u' + b(q, u) = 0``. The constraint forces are
resolved numerically (:mod:`pedalrepro.nonlinear.nonlinear_model`), which keeps the symbolic
expressions small. Coordinates that do not enter the dynamics on flat ground (contact-point
position, yaw, wheel rotation angles) are set to zero in the generated code.

Coordinates (Moore 2012; SymBRiM ``bicycle.q``): q1, q2 rear contact x, y; q3 yaw; q4 roll;
q5 pitch; q6 rear wheel angle; q7 steer; q8 front wheel angle. Roll q4 and steer q7 are the
benchmark roll and steer angles of Meijaard et al. (2007).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import sympy as sm
# sympy and sympy.physics.mechanics are imported where a model is derived (0.6 s): the jobs
# that load the cached model only need this module's constants and ModelOptions.

__all__ = [
    "LEG_BODIES", "IGNORABLE_Q", "STEER_DERIVATIVES", "ROLL", "PITCH", "STEER", "REAR_WHEEL",
    "ARM_PARAMETERS", "U_IND", "U_DEP", "ModelOptions", "SymbolicModel", "arm_loop_elbow", "derive",
]

#: Number of prescribed leg/crank bodies: left and right crank, shank, thigh.
LEG_BODIES: tuple[str, ...] = ("crank_r", "crank_l", "shank_r", "shank_l", "thigh_r", "thigh_l")
#: Indices (0-based, Moore order) of coordinates that do not enter the flat-ground dynamics.
IGNORABLE_Q: tuple[int, ...] = (0, 1, 2, 5, 7)
ROLL, PITCH, STEER = 3, 4, 6
REAR_WHEEL = 5
#: Symbols of the arm loops (one set; the left arm is the mirror image, y -> -y), see
#: :func:`_add_arms` and :mod:`pedalrepro.nonlinear.arms`.
ARM_PARAMETERS: tuple[str, ...] = (
    "arm_sx", "arm_sy", "arm_sz", "arm_hx", "arm_hy", "arm_hz", "arm_nx", "arm_ny", "arm_nz",
    "arm_a", "arm_b", "arm_cu",
    "arm_cf", "arm_sign", "arm_m_elbow", "arm_m_upper", "arm_m_fore")
#: Independent speeds: roll rate, rear wheel rate, steer rate.
U_IND: tuple[int, ...] = (3, 5, 6)
U_DEP: tuple[int, ...] = (0, 1, 2, 4, 7)


@dataclass(frozen=True)
class ModelOptions:
    """Options that change the symbolic model (and so the cache key).

    Parameters
    ----------
    legs
        Add the six prescribed leg and crank bodies (method NP). Without them the legs are part
        of the rigid rear-frame body (methods NT, the linearisation checks).
    arms
        Add the two arm loops of the city posture (CF, Fig 3.4): upper arm and forearm of each
        arm as particles whose positions are explicit functions of the steer angle
        (:func:`_add_arms`). Without them the arms are part of the rigid rear-frame body.
    """

    legs: bool = False
    arms: bool = False

    def key(self) -> str:
        return f"whipple{'_legs' if self.legs else ''}{'_arms' if self.arms else ''}"


@dataclass
class SymbolicModel:
    """The symbolic pieces the numeric code is generated from.

    Attributes
    ----------
    q, u
        Coordinates and speeds (8 each, Moore order).
    params
        Ordered parameter symbols (see :func:`parameter_names`).
    spec
        Ordered specified symbols of the prescribed leg motion (x, z, angle of each body in the
        rear frame and their first and second time derivatives); empty without legs.
    M, F
        Mass matrix (8 x 8) and forcing (8) of the unconstrained Kane equations.
    A, b
        Velocity constraint matrix (5 x 8) and acceleration constraint term (5).
    energy
        Total mechanical energy (kinetic + gravitational potential), J.
    """

    q: list
    u: list
    params: list
    spec: list
    M: sm.Matrix
    F: sm.Matrix
    A: sm.Matrix
    b: sm.Matrix
    energy: sm.Expr
    param_names: list[str]


def arm_loop_elbow(s_pt, h_pt, normal, a, b, sign, sqrt=None):
    """Elbow of one arm loop in closed form (3-tuples of rear-frame coordinates).

    The shoulder ``S`` is a flexion joint about the axis ``normal`` (unit, fixed in the trunk)
    followed by a rotation about the upper arm (SymBRiM ``FlexRotLeftShoulder``), the elbow a
    pin (``PinElbowStickLeftArm``) and the hand a ball joint on the handlebar
    (``HolonomicHandGrips``): the upper arm stays in the plane through ``S`` normal to
    ``normal`` (the sagittal plane for ``normal`` = lateral axis). With the grip ``H`` at
    ``dy = n . (H - S)`` from that plane, the forearm's projection on it has length
    ``b' = sqrt(b^2 - dy^2)``; the elbow is the intersection of the circles ``|E - S| = a`` and
    ``|E - H'| = b'`` in the plane, ``sign`` (+1 or -1) choosing the branch: ``E = S + t e1 +
    sign h e2`` with ``e1`` along ``H' - S`` and ``e2 = n x e1``.

    Works on sympy expressions and on numbers (``sqrt`` of the matching library; default
    ``sympy.sqrt``).
    """
    if sqrt is None:
        import sympy as sm

        sqrt = sm.sqrt
    r = [hc - sc for hc, sc in zip(h_pt, s_pt, strict=True)]
    n = normal
    dy = sum(ni * ri for ni, ri in zip(n, r, strict=True))
    rp = [ri - dy * ni for ri, ni in zip(r, n, strict=True)]
    d2 = rp[0] ** 2 + rp[1] ** 2 + rp[2] ** 2
    d = sqrt(d2)
    along = (a**2 - (b**2 - dy**2) + d2) / (2 * d)
    h = sqrt(a**2 - along**2)
    e2 = (n[1] * rp[2] - n[2] * rp[1], n[2] * rp[0] - n[0] * rp[2], n[0] * rp[1] - n[1] * rp[0])
    return tuple(sc + (along * rc + sign * h * ec) / d for sc, rc, ec in zip(s_pt, rp, e2,
                                                                            strict=True))


#: Derivatives of an arm coordinate with respect to the steer angle that Kane's equations need:
#: the position, the velocity's partial derivative and the acceleration's second derivative.
STEER_DERIVATIVES = 3


def _function_of_steer(name: str) -> list[type]:
    """``[f, f', f'']``: sympy functions of one argument whose derivative is the next one.

    An arm coordinate ``x(delta)`` enters Kane's equations through this placeholder, so that
    sympy forms velocities and accelerations by the chain rule (``d/dt f(q7) = f'(q7) q7'``)
    on small expressions; :func:`derive` puts the explicit ``x``, ``dx/ddelta`` and
    ``d2x/ddelta2`` in at the end. Kane's method on the explicit closed-form elbow took 294 of
    the 499 s that the two arm variants cost to derive and generate; with the placeholders they
    take 60 s, and the generated right-hand sides equal the old ones to 1e-14 relative.
    """
    import sympy as sm

    classes = [type(f"{name}_d{k}", (sm.Function,), {"nargs": 1})
               for k in range(STEER_DERIVATIVES)]
    for k, cls in enumerate(classes):
        nxt = classes[k + 1] if k + 1 < len(classes) else None

        def fdiff(self, argindex=1, _nxt=nxt, _name=cls.__name__):
            if _nxt is None:
                raise RuntimeError(f"{_name}: Kane's equations need no higher derivative")
            return _nxt(self.args[0])

        cls.fdiff = fdiff
    return classes


def _add_arms(bicycle, N, params: dict, steer) -> tuple[list, list]:
    """The six moving particles of the two arm loops (elbow, upper-arm COM, forearm COM each).

    Shoulder ``S`` (``arm_s*``, rear-frame coordinates from the rear wheel hub) and the
    shoulder flexion axis (``arm_n*``, unit) are fixed in the rear frame, the grip ``H``
    (``arm_h*``, front-frame coordinates from SymBRiM's steer hub on the steer axis) in the
    front frame; the left arm mirrors the right (``y -> -y``). Each
    segment is a rod of three particles reproducing its mass, COM and transverse central
    inertia (:mod:`pedalrepro.nonlinear.arms`); the particles at ``S`` and ``H`` are part of the
    rear and front frame bodies (numeric parameters), only the elbow particle
    (``arm_m_elbow``) and the two COM particles (``arm_m_upper`` at ``arm_cu * a`` from ``S``,
    ``arm_m_fore`` at ``arm_cf * b`` from ``E`` towards ``H``) move relative to the frames.

    Their rear-frame coordinates are functions of the steer angle ``steer`` (q7) alone; each
    enters the particle's position as a placeholder :func:`_function_of_steer`.

    Returns
    -------
    particles
        The six particles.
    coordinates
        ``(classes, x)`` per coordinate: the placeholder functions ``[f, f', f'']`` and the
        explicit coordinate ``x`` as an expression of ``steer``.
    """
    import sympy as sm
    from sympy.core.function import AppliedUndef
    from sympy.physics.mechanics import Particle, Point

    rear = bicycle.rear_frame
    front = bicycle.front_frame
    C = rear.body.frame
    hub = rear.wheel_hub.point
    steer_hub = front.steer_hub.point
    E_frame = front.body.frame
    p = params
    particles, coordinates = [], []
    for side, sy in (("r", 1), ("l", -1)):
        s_pt = (p["arm_sx"], sy * p["arm_sy"], p["arm_sz"])
        # mirror image of the right arm: the flexion axis reflected and reversed (-M n), so that
        # e2 = n x e1 is the reflected e2 and the same ``sign`` picks the mirrored elbow
        normal = (sy * p["arm_nx"], p["arm_ny"], sy * p["arm_nz"])
        grip = (steer_hub.pos_from(hub) + p["arm_hx"] * E_frame.x + sy * p["arm_hy"] * E_frame.y
                + p["arm_hz"] * E_frame.z)
        h_pt = tuple(grip.dot(ax) for ax in (C.x, C.y, C.z))
        e_pt = arm_loop_elbow(s_pt, h_pt, normal, p["arm_a"], p["arm_b"], p["arm_sign"])
        upper = tuple(s + p["arm_cu"] * (e - s) for s, e in zip(s_pt, e_pt, strict=True))
        fore = tuple(e + p["arm_cf"] * (h - e) for e, h in zip(e_pt, h_pt, strict=True))
        for label, xyz, mass in (("elbow", e_pt, p["arm_m_elbow"]),
                                 ("upper", upper, p["arm_m_upper"]),
                                 ("fore", fore, p["arm_m_fore"])):
            placeholders = []
            for axis, x in zip("xyz", xyz, strict=True):
                x = sm.sympify(x)
                functions = x.atoms(AppliedUndef)
                if functions - {steer}:
                    raise RuntimeError(f"arm {label}_{side} {axis} depends on more than the "
                                       f"steer angle: {functions}")
                classes = _function_of_steer(f"arm_{label}_{side}_{axis}")
                coordinates.append((classes, x))
                placeholders.append(classes[0](steer))
            point = Point(f"arm_{label}_{side}")
            point.set_pos(hub, placeholders[0] * C.x + placeholders[1] * C.y
                          + placeholders[2] * C.z)
            point.set_vel(N, point.pos_from(bicycle.ground.origin).dt(N))
            particles.append(Particle(f"arm_{label}_{side}", point, mass))
    return particles, coordinates


class _StageClock:
    """Adds the seconds since the previous mark to ``timings[name]`` (nothing when None)."""

    def __init__(self, timings: dict[str, float] | None) -> None:
        self.timings, self.last = timings, time.perf_counter()

    def stage(self, name: str) -> None:
        if self.timings is not None:
            now = time.perf_counter()
            self.timings[name] = self.timings.get(name, 0.0) + now - self.last
            self.last = now


def derive(options: ModelOptions, timings: dict[str, float] | None = None) -> SymbolicModel:
    """Derive the model symbolically with SymBRiM and Kane's method (a few seconds).

    Parameters
    ----------
    options
        Which bodies to include.
    timings
        When given, the seconds of each stage are added to it (``scripts/bench_derivation.py``):
        ``symbrim_assembly`` (SymBRiM's bicycle, the leg bodies and the arm loops),
        ``kane_equations`` (mass matrix and forcing), ``constraints_energy`` (velocity
        constraints, their derivative, the energy) and ``substitution`` (plain symbols, explicit
        arm coordinates).

    Returns
    -------
    SymbolicModel
    """
    import symbrim as sb
    import sympy as sm
    from sympy.core.function import AppliedUndef
    from sympy.physics.mechanics import (
        KanesMethod,
        Point,
        ReferenceFrame,
        RigidBody,
        dynamicsymbols,
        inertia,
    )

    clock = _StageClock(timings)
    t = dynamicsymbols._t
    bicycle = sb.WhippleBicycle("bicycle")
    bicycle.ground = sb.FlatGround("ground")
    bicycle.rear_frame = sb.RigidRearFrame("rear_frame")
    bicycle.front_frame = sb.RigidFrontFrame("front_frame")
    bicycle.rear_wheel = sb.KnifeEdgeWheel("rear_wheel")
    bicycle.front_wheel = sb.KnifeEdgeWheel("front_wheel")
    bicycle.rear_tire = sb.NonHolonomicTire("rear_tire")
    bicycle.front_tire = sb.NonHolonomicTire("front_tire")
    bicycle.define_all()
    system = bicycle.to_system()
    g = sm.Symbol("g")
    normal = bicycle.ground.get_normal(bicycle.ground.origin)
    N = bicycle.ground.frame
    q = list(bicycle.q)
    u = list(bicycle.u)

    bodies = list(system.bodies)
    spec: list = []
    leg_params: list = []
    if options.legs:
        rear = bicycle.rear_frame.body
        hub = bicycle.rear_frame.wheel_hub.point
        pos_syms, ang_syms = [], []
        for name in LEG_BODIES:
            x, z, th = dynamicsymbols(f"{name}_x {name}_z {name}_th")
            y, m, i_perp = sm.symbols(f"{name}_y {name}_m {name}_I")
            frame = ReferenceFrame(f"{name}_frame")
            frame.orient_axis(rear.frame, rear.frame.y, th)
            point = Point(f"{name}_com")
            point.set_pos(hub, x * rear.frame.x + y * rear.frame.y + z * rear.frame.z)
            point.set_vel(N, point.pos_from(bicycle.ground.origin).dt(N))
            # Slender rod along the body's own x axis (Sec 2.1.1 segments).
            body = RigidBody(name, point, frame, m, (inertia(frame, 0, i_perp, i_perp), point))
            bodies.append(body)
            pos_syms += [x, z, th]
            leg_params += [y, m, i_perp]
            ang_syms.append(th)
        spec = pos_syms
    arm_coordinates: list = []
    if options.arms:
        particles, arm_coordinates = _add_arms(
            bicycle, N, {n: sm.Symbol(n) for n in ARM_PARAMETERS}, q[STEER])
        bodies += particles
    # Gravity as forces on every mass centre and arm particle (SymBRiM's apply_uniform_gravity
    # does the same).
    loads = [(b.masscenter, -g * b.mass * normal) for b in bodies]
    # SymBRiM's Moore model defines every speed as u_i = q_i' (checked here).
    kdes = [ui - qi.diff(t) for qi, ui in zip(q, u, strict=True)]
    qd_u = dict(zip([qi.diff(t) for qi in q], u, strict=True))
    if set(sm.Matrix(system.kdes).xreplace(qd_u)) - {0}:
        raise RuntimeError("unexpected kinematic differential equations in SymBRiM's model")
    clock.stage("symbrim_assembly")
    km = KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kdes, bodies=bodies, forcelist=loads)
    km.kanes_equations(bodies, loads)
    clock.stage("kane_equations")
    qd_to_u = km.kindiffdict()
    M = km.mass_matrix
    F = km.forcing

    # Constraints: no-slip (4 nonholonomic) and the derivative of the holonomic one.
    hol = sm.Matrix(system.holonomic_constraints)
    nh = sm.Matrix(system.nonholonomic_constraints)
    vel = sm.Matrix.vstack(nh, hol.diff(t)).xreplace(qd_to_u)
    A = vel.jacobian(u)
    rest = (vel - A * sm.Matrix(u)).xreplace({ui: 0 for ui in u}).expand()
    if any(e != 0 for e in rest):
        raise RuntimeError("velocity constraints are not homogeneous in the speeds")
    # d/dt (A u) = A u' + b, b = (dA/dt) u
    b = (A * sm.Matrix(u)).diff(t).xreplace(qd_to_u)
    b = b.xreplace({ui.diff(t): 0 for ui in u})

    # Energy: kinetic + gravitational potential (height along the ground normal).
    ke = sum(body.kinetic_energy(N) for body in bodies)
    pe = sum(body.mass * g * body.masscenter.pos_from(bicycle.ground.origin).dot(normal)
             for body in bodies)
    energy = (ke + pe).xreplace(qd_to_u)
    clock.stage("constraints_energy")

    # Replace specified functions and their derivatives by plain symbols for code generation.
    spec_syms: list = []
    repl: dict = {}
    for level in (2, 1, 0):
        for s in spec:
            sym = sm.Symbol(f"{s.func.__name__}_d{level}")
            repl[s.diff(t, level) if level else s] = sym
    for level in (0, 1, 2):
        spec_syms += [repl[s.diff(t, level) if level else s] for s in spec]
    ignorable = {q[i]: 0 for i in IGNORABLE_Q}

    def clean(expr):
        # derivatives first (xreplace matches whole subtrees), then the functions themselves
        expr = expr.xreplace({k: v for k, v in repl.items() if k.is_Derivative})
        expr = expr.xreplace(repl)
        return expr.xreplace(ignorable)

    M, F, A, b = (clean(x) for x in (M, F, A, b))
    energy = clean(energy)
    # qs and us as plain symbols.
    q_s = sm.symbols("q1:9")
    u_s = sm.symbols("u1:9")
    to_plain = dict(zip(q, q_s, strict=True)) | dict(zip(u, u_s, strict=True))
    M, F, A, b = (x.xreplace(to_plain) for x in (M, F, A, b))
    energy = energy.xreplace(to_plain)
    # (the arm placeholders are sympy Function classes, not undefined functions of time)
    leftovers = {f for x in (M, F, A, b, sm.Matrix([energy])) for f in x.atoms(AppliedUndef)}
    if leftovers:
        raise RuntimeError(f"unresolved functions of time in the model: {leftovers}")
    # The explicit arm coordinates and their steer derivatives in place of the placeholders
    # (the parameters are collected from the small expressions before).
    free = (M.free_symbols | F.free_symbols | A.free_symbols | b.free_symbols
            | energy.free_symbols)
    explicit: dict = {}
    for classes, x in arm_coordinates:
        x = x.xreplace(to_plain)
        free |= x.free_symbols
        for k, cls in enumerate(classes):
            x = x.diff(q_s[STEER]) if k else x  # only the derivatives the placeholders stand for
            explicit[cls(q_s[STEER])] = x
    if explicit:
        M, F, energy = M.xreplace(explicit), F.xreplace(explicit), energy.xreplace(explicit)
    params = sorted(free - set(q_s) - set(u_s) - set(spec_syms) - {t}, key=lambda s: s.name)
    clock.stage("substitution")
    return SymbolicModel(list(q_s), list(u_s), params, spec_syms, M, F, A, b, energy,
                         [s.name for s in params])
