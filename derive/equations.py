"""Lagrange's equations and everything a time integrator needs, from the energies.

The results are SymPy expressions in the symbols of :class:`~rocking.derive.mechanics.System`
(``s``, coordinates, velocities, the ground acceleration ``ag``, its vertical
component ``agy`` and the parameters). Each is derived, never typed: the rocking
equations as mass matrix and forcing, the full-contact accelerations, the uplift
functions as the reaction that keeps ``theta = 0``, the impact map from
conservation laws, the mechanical energy and its rate, and the static critical
angle.

The vertical ground acceleration ``ddy_g`` enters the equations of motion and the
reactions of a model whose energies hold ``g`` in the weights alone only with
gravity, as ``g + ddy_g`` (:func:`vertical_as_gravity` checks it on every model):
those are kept at ``ddy_g = 0`` with ``g`` standing for the effective gravity, so
that a runtime without vertical motion computes what it did before, and a runtime
with it passes ``g + ddy_g(t)`` where ``g`` goes. A model that uses ``g`` elsewhere
(a spring preloaded by a weight) is derived at ``ddy_g = 0`` and takes no vertical
motion (``Equations.vertical``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from .mechanics import System, ag, agy, build_system, pad_power, s
from .spec import IMPACT_LAWS, INERTIA_OPTIONS, Spec, SpecError, nonnegative

DEFAULT_OPTIONS = {"impact": "spec", "inertia": "free"}
#: The expressions of :class:`Equations` written at ``ddy_g = 0`` with ``g`` standing for the
#: effective gravity ``g + ddy_g`` when ``Equations.vertical`` (:func:`vertical_as_gravity`).
EFFECTIVE_GRAVITY = ("forcing", "rocking_accel", "contact_accel", "uplift", "base_reaction")


@dataclass(frozen=True)
class Equations:
    """The derived model.

    Attributes
    ----------
    system : System
        Symbols and energies the equations come from.
    options : dict
        Resolved derivation options (per-coordinate impact laws included).
    mass_matrix : Matrix
        ``M(q)`` of the rocking phase, ``M ddq = forcing``. The forcing, the
        accelerations, the uplift function and the base reaction are written at
        ``ddy_g = 0``, their ``g`` standing for the effective gravity ``g + ddy_g``
        (:data:`EFFECTIVE_GRAVITY`) when ``vertical``.
    forcing : Matrix
        Right-hand side of the rocking phase.
    rocking_accel : list of Expr
        ``ddq`` of the rocking phase, solved so that ``ddtheta`` stays finite
        when the attached masses vanish.
    contact_accel : list of Expr
        ``ddq`` in full contact (``ddtheta = 0``).
    uplift : Expr
        Positive when the block would uplift about the pivot ``s``.
    impact : list of Expr
        Velocities after an impact at ``theta = 0`` that ends rocking about
        ``s`` (the new pivot is ``-s``); coordinates are continuous.
    energy, power : Expr
        Mechanical energy in the ground frame (with the true ``g``) and its rate
        along solutions (dissipation plus the work of the inertial ground force,
        both components).
    critical_angle : Expr
        Static critical angle about the pivot ``s`` (sign of ``s``).
    critical_tangent : Expr
        Its tangent where the weights' centre is above the ground (then the
        angle is ``atan`` of it), NaN elsewhere: a runtime can tell that an
        angle is below the critical one without an ``atan2``.
    uplift_energy : Expr
        Least energy above rest, in full contact without ground motion, at
        which the attached bodies can lift the block about ``s``; ``oo`` when
        they cannot, 0 when no bound could be derived.
    least_potential, least_stroke_potential : Expr
        Least potential energy at the tilt ``theta`` about ``s`` over every
        position of the attached bodies (``least_potential``), or over those
        after ``q[1]`` with ``q[1]`` held (``least_stroke_potential``), the
        bumpers' energy left out; ``-oo`` where it has no least value, and
        wherever the energy could grow without ground motion (no early verdict,
        :func:`least_potentials`).
    stop_gaps : list of Expr
        Per side of every end stop, the penetration ``delta``: its bumper acts
        while it is > 0 (docs/model.md section 11); a runtime stops at its zeros.
    stop_forces : list of Expr
        Per side of every end stop, the bumper's force on the travel,
        ``max(0, k_b delta + c_b ddelta)`` (Hunt-Crossley: ``max(0, k_b delta^n (1 +
        chi ddelta / v_in))``) while ``delta > 0``, else 0 (positive: pushes back; a
        pad only pushes).
    stop_contact : list of Expr
        Per side of every end stop, ``min(delta, k_b delta + c_b ddelta)``
        (Hunt-Crossley: ``min(delta, v_in + chi ddelta)``): > 0 exactly while its
        bumper pushes; a runtime stops at its zeros.
    block_accelerations : list of Expr
        Absolute horizontal accelerations of the centre of the block's top side and of
        its centroid ``G``, each affine in the accelerations ``ddq``: the part free of
        them, then the coefficient of each (:func:`affine_in_accelerations`).
    base_reaction : list of Expr
        The base shear ``V_b`` (the ground's horizontal force on the block and its
        bodies, positive to the right), the ground's vertical force ``N_b`` (positive
        up) and the overturning moment ``M_b`` (minus the moment of the ground's
        reaction about the centre of the base, positive counter-clockwise), each
        affine in ``ddq`` like ``block_accelerations`` (:func:`base_reaction`).
    element_forces : list of Expr
        Per attached coordinate, the force (a moment for an angle) of its springs,
        dashpots and bumpers on the block along it: ``dV_e/dq + dD/ddq`` with ``V_e``
        the potential but the weights'; for ``omd`` the guide force ``k_m x + c dx``
        plus the bumpers'.
    stop_regime : list of Expr
        Per side of every end stop, its indicator as the condition on the state:
        1 while its bumper pushes (``stop_contact > 0``), else 0; then, per
        Hunt-Crossley side, its memory ``v_in`` as ``max(ddelta, floor)``. The forcing,
        accelerations, uplift, energy and power are written with the indicators and
        memories themselves (``System.stops``), the regime of the stops being an input
        like the pivot ``s``; this is the regime of a state when no other is given.
    stop_memory : list of Symbol
        The memory ``v_in`` of each Hunt-Crossley side, in side order: the regime's
        inputs after the indicators.
    stop_approach : list of Expr
        Per side of every end stop, the rate of its penetration ``ddelta``: where a
        contact starts (``ddelta >= 0``), ``max(ddelta, floor)`` is its ``v_in``.
    vertical : bool
        Whether the vertical ground acceleration enters the equations and reactions
        only with gravity (:func:`vertical_as_gravity`): then a runtime takes vertical
        motion, else it refuses it.
    """

    system: System
    options: dict
    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    rocking_accel: list
    contact_accel: list
    uplift: sp.Expr
    impact: list
    energy: sp.Expr
    power: sp.Expr
    critical_angle: sp.Expr
    critical_tangent: sp.Expr
    uplift_energy: sp.Expr
    least_potential: sp.Expr
    least_stroke_potential: sp.Expr
    stop_gaps: Sequence = ()
    stop_forces: Sequence = ()
    stop_contact: Sequence = ()
    block_accelerations: Sequence = ()
    base_reaction: Sequence = ()
    element_forces: Sequence = ()
    stop_regime: Sequence = ()
    stop_memory: tuple = ()
    stop_approach: tuple = ()
    vertical: bool = True


def resolve_options(spec: Spec, options: dict | None) -> dict:
    """Check ``options`` and resolve the impact law of every coordinate."""
    opts = dict(DEFAULT_OPTIONS)
    for key, value in (options or {}).items():
        if key not in DEFAULT_OPTIONS:
            raise SpecError(f"unknown option {key!r}; options are {', '.join(DEFAULT_OPTIONS)}")
        opts[key] = value
    if opts["inertia"] not in INERTIA_OPTIONS:
        raise SpecError(
            f"option inertia: unknown value {opts['inertia']!r}; choose one of {', '.join(INERTIA_OPTIONS)}"
        )
    if opts["impact"] not in ("spec",) + IMPACT_LAWS:
        raise SpecError(
            f"option impact: unknown value {opts['impact']!r}; choose one of spec, {', '.join(IMPACT_LAWS)}"
        )
    laws = dict(spec.impact) if opts["impact"] == "spec" else {c: opts["impact"] for c in spec.coordinates}
    return {"impact": opts["impact"], "impact_laws": laws, "inertia": opts["inertia"]}


def _reduce(expr):
    """Canonical form: expanded, ``s**2 = 1``, ``sin**2 = 1 - cos**2``."""
    expr = sp.expand(expr)
    expr = expr.replace(
        lambda a: a.is_Pow and a.base == s and a.exp.is_Integer,
        lambda a: s ** (int(a.exp) % 2),
    )
    expr = expr.replace(
        lambda a: a.is_Pow and isinstance(a.base, sp.sin) and a.exp.is_Integer and a.exp >= 2,
        lambda a: a.base ** (int(a.exp) % 2) * (1 - sp.cos(a.base.args[0]) ** 2) ** (int(a.exp) // 2),
    )
    return sp.expand(expr)


def _to_symbols(expr, sysm: System, vg):
    """Replace the time functions and their derivatives by plain symbols.

    Both ground velocities become ``vg``: no equation may depend on either.
    """
    t_ = sysm.x_g.args[0]
    rep = {sysm.x_g.diff(t_, 2): ag, sysm.x_g.diff(t_): vg, sysm.y_g.diff(t_, 2): agy, sysm.y_g.diff(t_): vg}
    for f, _q, dq, ddq in zip(sysm.qt, sysm.q, sysm.dq, sysm.ddq):
        rep[f.diff(f.args[0], 2)] = ddq
        rep[f.diff(f.args[0])] = dq
    expr = expr.xreplace(rep)
    return expr.xreplace(dict(zip(sysm.qt, sysm.q)))


def _relative(X, sysm: System):
    """The position ``X`` relative to the ground (its displacement taken out)."""
    return X - sp.Matrix([sysm.x_g, sysm.y_g])


def _at_rest_ground(expr, sysm: System):
    """``expr`` with the ground's displacement at 0: positions relative to the ground."""
    return expr.xreplace({sysm.x_g: 0, sysm.y_g: 0}).doit()


def _gravity(sysm: System):
    """The symbol of gravity among the parameters."""
    return sysm.params[[p.name for p in sysm.params].index("g")]


def vertical_as_gravity(exprs, sysm: System) -> bool:
    """Whether ``ddy_g`` enters ``exprs`` only with gravity, as ``g + ddy_g``.

    In the frame that moves with the ground, its vertical acceleration is an
    inertial force ``-m ddy_g`` on every body, parallel to its weight ``-m g``:
    each body feels the effective gravity ``g + ddy_g``, and Lagrange's equations
    on the absolute positions say so, unless ``g`` enters the energies elsewhere
    (a spring preloaded by a weight keeps its preload when the ground moves).
    """
    g = _gravity(sysm)
    return all(_reduce(e - e.xreplace({agy: 0}).xreplace({g: g + agy})) == 0 for e in exprs)


def still(exprs) -> list:
    """``exprs`` at ``ddy_g = 0``."""
    return [e.xreplace({agy: 0}) for e in exprs]


def lagrange(sysm: System):
    """Residuals ``d/dt dT/ddq - dT/dq + dV/dq + dD/ddq`` of every coordinate."""
    t_ = sysm.x_g.args[0]
    vg = sp.Symbol("vg", real=True)
    out = []
    for f in sysm.qt:
        v = f.diff(t_)
        r = sysm.T.diff(v).diff(t_) - sysm.T.diff(f) + sysm.V.diff(f) + sysm.D.diff(v)
        r = _reduce(_to_symbols(r, sysm, vg))
        if r.has(vg) or r.has(sysm.x_g) or r.has(sysm.y_g):
            raise SpecError("the equations depend on the ground velocity or position: the model is inconsistent")
        out.append(r)
    return out


def _schur_solve(A, rhs, finite=True):
    """Solve ``A u = rhs`` by the Schur complement of the first unknown.

    ``A[1:, 1:]`` belongs to the attached bodies and is proportional to their
    masses, as is the coupling ``A[1:, 0]``; cancelling their ratio first keeps
    ``u[0]`` finite as the masses go to zero.
    """
    n = A.shape[0]
    if n == 1:
        return [sp.cancel(rhs[0] / A[0, 0])]
    a, c, b, Dm = A[0, 0], A[0, 1:], A[1:, 0], A[1:, 1:]
    Dinv_b = Dm.LUsolve(b).applyfunc(sp.cancel)
    cT_Dinv = Dm.T.LUsolve(c.T).applyfunc(sp.cancel).T
    u0 = (rhs[0] - (cT_Dinv * rhs[1:, 0])[0]) / _reduce(a - (c * Dinv_b)[0])
    Dinv_rhs = Dm.LUsolve(rhs[1:, 0])
    if finite:
        Dinv_rhs = Dinv_rhs.applyfunc(sp.cancel)
    rest = Dinv_rhs - Dinv_b * u0
    return [u0] + list(rest)


def _angular_momentum(sysm: System, pivot_sign, velocities):
    """Angular momentum about the corner ``-pivot_sign`` at ``theta = 0``.

    Bodies move as while rocking about ``pivot_sign`` with ``velocities``.
    """
    t_ = sysm.x_g.args[0]
    B = sysm.params[[p.name for p in sysm.params].index("B")]
    point = sp.Matrix([pivot_sign * B / 2, 0])
    vg = sp.Symbol("vg", real=True)
    total = sp.Integer(0)
    for mass, inertia, X, angle in sysm.bodies:
        Xr = _relative(X, sysm)
        V = Xr.diff(t_)
        omega = (sysm.qt[0] + angle).diff(t_)
        r = Xr - point
        total += mass * (r[0] * V[1] - r[1] * V[0]) + inertia * omega
    total = _to_symbols(total, sysm, vg).subs(s, pivot_sign).subs(sysm.q[0], 0)
    return _reduce(total.xreplace(dict(zip(sysm.dq, velocities))))


def impact_map(sysm: System, laws: dict):
    """Velocities after an impact ending rocking about ``s``.

    The total angular momentum about the new pivot ``-s`` is conserved; each
    attached coordinate keeps either its generalised momentum (``"momentum"``:
    no impulse acts along it) or its velocity (``"velocity"``).
    """
    plus = tuple(sp.Symbol(d.name + "_plus", real=True) for d in sysm.dq)
    vg = sp.Symbol("vg", real=True)
    T_rel = _to_symbols(_at_rest_ground(sysm.T, sysm), sysm, vg).subs(vg, 0)
    names = [str(q) for q in sysm.q]
    eqs = [_angular_momentum(sysm, -s, plus) - _angular_momentum(sysm, s, sysm.dq)]
    unknowns = [plus[0]]
    known = {}
    for j in range(1, len(sysm.q)):
        if laws[names[j]] == "velocity":
            known[plus[j]] = sysm.dq[j]
            continue
        p_j = T_rel.diff(sysm.dq[j]).subs(sysm.q[0], 0)
        after = p_j.subs(s, -s).xreplace(dict(zip(sysm.dq, plus)))
        eqs.append(_reduce(after - p_j))
        unknowns.append(plus[j])
    eqs = [_reduce(e.xreplace(known)) for e in eqs]
    A = sp.Matrix([[sp.diff(e, u) for u in unknowns] for e in eqs])
    rhs = -sp.Matrix([e.xreplace({u: 0 for u in unknowns}) for e in eqs])
    sol = dict(zip(unknowns, _schur_solve(A, rhs)))
    sol.update(known)
    return [sol[p] for p in plus]


def _weights_moment(sysm: System):
    """``(a, b)`` of the weights' potential ``a cos(theta) + b sin(theta)`` about the pivot.

    ``a`` is the weights' height term (their centre above the ground when
    positive), ``b`` their lever arm; gravity's moment about the pivot
    vanishes at ``atan2(b, a)``, the other coordinates held.
    """
    vg = sp.Symbol("vg", real=True)
    g = _gravity(sysm)
    Vg = sp.Integer(0)
    for mass, _, X, _ in sysm.bodies:
        Vg += mass * g * _relative(X, sysm)[1]
    Vg = _to_symbols(Vg, sysm, vg)
    theta = sysm.q[0]
    if sp.simplify(Vg.diff(theta, 2) + Vg) != 0:
        raise SpecError("the gravity potential is not of the form a cos(theta) + b sin(theta)")
    return _reduce(Vg.subs(theta, 0)), _reduce(Vg.diff(theta).subs(theta, 0))


def critical_angle(a, b):
    """Angle where gravity's moment about the pivot vanishes, other coordinates held (:func:`_weights_moment`)."""
    return sp.atan2(b, a)


def critical_tangent(a, b):
    """``tan`` of :func:`critical_angle` where ``a > 0`` (the angle is then ``atan(b / a)``), NaN elsewhere."""
    return sp.Piecewise((b / a, a > 0), (sp.nan, True))


def _least_uplift_energy(E, u, z):
    """Least ``E`` on ``u >= 0`` for ``E`` quadratic and ``u`` affine in ``z``, or ``None`` if they are not.

    With ``E = E* + w^T Q w / 2`` about its minimum ``z* = -Q^-1 b`` (``b`` the
    gradient of ``E`` at ``z = 0``) and ``u = u* + a^T w``, the least ``E`` is
    ``E* + max(0, -u*)^2 / (2 a^T Q^-1 a)``, written with ``adj(Q) / det(Q)``
    so that it stays finite when ``Q`` is singular and ``b = 0``.
    """
    Q = sp.hessian(E, z)
    a = sp.Matrix([sp.diff(u, v) for v in z])
    at_zero = {v: 0 for v in z}
    b = sp.Matrix([sp.diff(E, v) for v in z]).subs(at_zero)
    e0 = E.subs(at_zero)
    zv = sp.Matrix(z)
    quadratic = not any(Q.has(v) for v in z) and _reduce(E - (zv.T * Q * zv)[0] / 2 - (b.T * zv)[0] - e0) == 0
    if not (quadratic and not any(a.has(v) for v in z)):
        return None
    det = sp.factor(Q.det())
    spread = _reduce((a.T * Q.adjugate() * a)[0])
    u0 = u.subs(at_zero)
    if b.is_zero_matrix and e0 == 0:
        return sp.Max(0, -u0) ** 2 * det / (2 * spread)
    adj_b = Q.adjugate() * b
    least = _reduce(e0 - (b.T * adj_b)[0] / (2 * det))
    u_least = _reduce(u0 - (a.T * adj_b)[0] / det)
    return least + sp.Max(0, -u_least) ** 2 * det / (2 * spread)


def _stop_regions(sysm: System) -> list[dict]:
    """Every assignment of the stops' indicators with at most one side of each stop acting, all off first."""
    regions: list[dict] = [{}]
    for on, _, _, _, stop, _ in sysm.stops:
        sides = [o for o, _, _, _, j, _ in sysm.stops if j == stop]
        regions = [{**r, on: 0} for r in regions] + [{**r, on: 1} for r in regions if not any(r.get(o) for o in sides)]
    return regions


def uplift_energy(sysm: System, energy, uplift):
    """Least energy above rest at which the attached bodies can lift the block.

    In full contact after the pulse the energy can only fall (the power is
    ``-2 D``), so once it is below this bound the block can never uplift
    again. Within each region of the stops (no bumper acting, or one side of
    some stops) ``E`` is quadratic and ``u`` affine in the attached bodies'
    state ``z`` (:func:`_least_uplift_energy`); the least of the regions' bounds,
    each taken over all ``z``, is a bound for the whole. Other energies get no
    bound (0).
    """
    if len(sysm.q) == 1:
        return sp.oo
    rest = {sysm.q[0]: 0, sysm.dq[0]: 0, ag: 0}
    z = list(sysm.q[1:]) + list(sysm.dq[1:])
    at_zero = {v: 0 for v in z}
    off = {on: 0 for on, *_ in sysm.stops}
    E_rest = energy.subs(rest).subs(at_zero).subs(off)
    bounds = []
    for region in _stop_regions(sysm):
        E = _reduce(energy.subs(rest).subs(region) - E_rest)
        bound = _least_uplift_energy(E, _reduce(uplift.subs(rest).subs(region)), z)
        if bound is None:
            return sp.Integer(0)
        bounds.append(bound)
    return bounds[0] if len(bounds) == 1 else sp.Min(*bounds)


def _least_over(V, z):
    """Least value of ``V`` over ``z``; ``None`` unless ``V`` is quadratic in ``z`` with a Hessian free of ``z``.

    With ``V = V0 + b^T z + z^T Q z / 2`` the least value is
    ``V0 - b^T adj(Q) b / (2 det Q)`` where ``Q`` is positive definite (its
    leading minors are positive), ``-oo`` elsewhere (``V`` is unbounded below,
    or the bound is not derived).
    """
    if not z:
        return V
    Q = sp.hessian(V, z)
    at_zero = {v: 0 for v in z}
    b = sp.Matrix([sp.diff(V, v) for v in z]).subs(at_zero)
    v0 = V.subs(at_zero)
    zv = sp.Matrix(z)
    if any(Q.has(v) for v in z) or _reduce(V - (zv.T * Q * zv)[0] / 2 - (b.T * zv)[0] - v0) != 0:
        return None
    definite = sp.And(*[sp.factor(Q[:k, :k].det()) > 0 for k in range(1, len(z) + 1)])
    least = v0 - (b.T * Q.adjugate() * b)[0] / (2 * sp.factor(Q.det()))
    return sp.Piecewise((least, definite), (-sp.oo, True))


def energy_cannot_grow(spec: Spec, laws: dict) -> bool:
    """Whether the mechanical energy can only fall once the ground is still.

    Between impacts its rate is ``-2 D``: every dashpot's and bumper's damping
    must be >= 0. At an impact, the momentum law is a plastic impact at the new
    pivot, which never adds energy (Carnot's theorem; docs/model.md 10.5); the
    velocity law can. Bumpers must store energy, not release it: stiffness >= 0.
    """
    coefficients = [d.coefficient for d in spec.dashpots]
    coefficients += [c for stop in spec.stops for c in (stop.damping, stop.stiffness)]
    momentum = all(law == "momentum" for law in laws.values())
    return momentum and all(nonnegative(c, spec.all_parameters) for c in coefficients)


def least_potentials(sysm: System, energy, spec: Spec, laws: dict) -> tuple:
    """``least_potential`` and ``least_stroke_potential`` of :class:`Equations` (docs/simulation.md, rule 4).

    The potential is the energy at rest velocities with every bumper clear:
    a bumper only adds its ``k_b delta^2 / 2 >= 0``, so the least value is a
    lower bound for every regime. After the ground has stopped and while the
    energy cannot grow (:func:`energy_cannot_grow`), a state whose energy is
    below the least potential at a tilt can never reach that tilt. Both are
    ``-oo`` (no bound) unless the potential is ``a cos(theta) + b sin(theta)``
    plus terms free of ``theta``, with ``a`` and ``b`` proportional to ``g``
    and quadratic in the attached coordinates (so that the runtime can bound
    it on an arc of tilts, rule 4), and unless every end stop's gap is affine
    in ``q[1]`` alone (the runtime checks them at the largest stroke).
    """
    none = (-sp.oo, -sp.oo)
    if not energy_cannot_grow(spec, laws):
        return none
    theta = sysm.q[0]
    g = _gravity(sysm)
    off = {on: 0 for on, *_ in sysm.stops}
    V = _reduce(energy.xreplace(off).subs({d: 0 for d in sysm.dq}))
    weights = _reduce(g * V.diff(g))
    if _reduce(weights.diff(theta, 2) + weights) != 0 or _reduce(V - weights).has(theta, g):
        return none
    vg = sp.Symbol("vg", real=True)
    for _, delta, *_ in sysm.stops:
        gap = _to_symbols(delta, sysm, vg)
        stroke = sysm.q[1] if len(sysm.q) > 1 else None
        others = [q for q in sysm.q if q != stroke]
        if stroke is None or gap.has(*others) or not (gap.is_polynomial(stroke) and sp.degree(gap, stroke) <= 1):
            return none
    least = _least_over(V, list(sysm.q[1:]))
    stroke = _least_over(V, list(sysm.q[2:]))
    if least is None or stroke is None:
        return none
    return least, stroke


def stop_memories(sysm: System, approaches: list) -> dict:
    """Each Hunt-Crossley side's memory symbol ``v_in`` -> ``max(ddelta, floor)``: its value where a contact starts.

    The memory of a state given no other: its contact taken to start there
    (docs/model.md section 11, as at the start of a run).
    """
    return {
        pad.approach: sp.Max(rate, sp.Float(pad.approach_floor))
        for (*_, pad), rate in zip(sysm.stops, approaches)
        if pad.hunt_crossley
    }


def stop_indicators(sysm: System, contacts: list, memory: dict) -> dict:
    """Each stop side's indicator symbol -> 1 while its bumper pushes (its ``contacts`` > 0), else 0.

    The regime of a state (with the memory ``memory`` of :func:`stop_memories`). A pad pushes
    while the mass is beyond the gap and its force is compressive: an unbonded pad cannot pull
    (docs/model.md section 11).
    """
    return {
        on: sp.Piecewise((1, contact.xreplace(memory) > 0), (0, True))
        for (on, *_), contact in zip(sysm.stops, contacts)
    }


def in_penetrations(expr, sysm: System, vg):
    """``expr`` with the terms of each bumper written with its penetration: ``k_b (x - L)``, not ``k_b x - k_b L``.

    Expanded, a bumper's force is a difference of terms much larger than itself
    near the stop, where it matters; in every sum, the terms of a side's
    indicator ``on`` are gathered and divided by its penetration ``delta``
    (when ``delta`` is linear in a coordinate), so that the code computes
    ``delta`` first. The quotient's term and each term of the remainder keep
    their own factor ``on``: a runtime that holds the regime constant folds
    ``on`` into the constants of a run, where a remainder term such as
    ``on c_b dx`` joins the other terms in ``dx``.
    """
    for on, delta, *_ in sysm.stops:
        d = _to_symbols(delta, sysm, vg)
        coordinate = next((q for q in sysm.q if sp.degree(d, q) == 1 and d.is_polynomial(q)), None)
        if coordinate is None:
            continue

        def gather(add, on=on, d=d, q=coordinate):
            acting = [term for term in add.args if term.has(on)]
            others = [term for term in add.args if not term.has(on)]
            bumper = sp.expand(sp.Add(*acting) / on)
            if bumper.has(on) or not bumper.is_polynomial(q):
                return add
            quotient, remainder = sp.div(bumper, d, q)
            terms = [on * term for term in sp.Add.make_args(sp.expand(remainder))]
            if quotient != 0:
                terms.append(sp.Mul(on, quotient, d, evaluate=False))
            return sp.Add(*others, *terms)

        expr = expr.replace(lambda e, on=on: e.is_Add and any(t.has(on) for t in e.args), gather)
    return expr


def stop_gaps_and_forces(sysm: System, vg) -> tuple[list, list, list]:
    """Per stop side: the penetration, the bumper's force on it (0 while it does not push) and its contact.

    The contact ``min(delta, bracket)`` is > 0 exactly where the pad pushes:
    beyond the gap, with a compressive force (:meth:`Pad.push`). Its zeros
    are the gap closing or opening and the force crossing 0, where the bumper's
    force has a kink: the events of the regime (docs/simulation.md, rule 6).
    """
    t_ = sysm.x_g.args[0]
    gaps = [_reduce(_to_symbols(delta, sysm, vg)) for _, delta, *_ in sysm.stops]
    brackets, pushes = [], []
    for (_, delta, k, c, _, pad), gap in zip(sysm.stops, gaps):
        bracket, push = pad.push(k, c, gap, _reduce(_to_symbols(delta.diff(t_), sysm, vg)))
        brackets.append(bracket)
        pushes.append(push)
    contacts = [sp.Min(gap, bracket) for gap, bracket in zip(gaps, brackets)]
    forces = [on * push for (on, *_), push in zip(sysm.stops, pushes)]
    return gaps, forces, contacts


def stop_approaches(sysm: System, vg) -> list:
    """Per stop side, the rate of its penetration ``ddelta``: at a contact's start, the approach speed ``v_in``."""
    t_ = sysm.x_g.args[0]
    return [_reduce(_to_symbols(delta.diff(t_), sysm, vg)) for _, delta, *_ in sysm.stops]


def clip_pad_powers(expr):
    """``expr`` with every Hunt-Crossley power of a penetration written out as ``max(delta, 0)^p``, for the printers.

    Where a side does not act its terms carry the factor ``on = 0``, but ``delta^n`` of a
    negative ``delta`` is NaN, and ``0 NaN`` is NaN: clipped, the product is 0.
    """
    return expr.replace(lambda e: isinstance(e, pad_power), lambda e: sp.Max(e.args[0], 0) ** e.args[1])


def affine_in_accelerations(expr, sysm: System) -> list:
    """``[expr at ddq = 0, d expr / d ddq_0, ...]``: ``expr`` is affine in the accelerations.

    The generated functions take the state and ``ag``, never the accelerations (those are
    the runtime's, of the phase it is in): an expression of them is handed over as its
    coefficients, ``expr = out[0] + sum_j out[1 + j] ddq_j``.
    """
    expr = _reduce(expr)
    free = _reduce(expr.xreplace({a: 0 for a in sysm.ddq}))
    coefficients = [_reduce(expr.diff(a)) for a in sysm.ddq]
    if any(c.has(*sysm.ddq) for c in coefficients):
        raise SpecError("an acceleration of the block or a reaction is not linear in the accelerations")
    return [free, *coefficients]


def _absolute_acceleration(X, sysm: System, vg):
    """The absolute acceleration of the position ``X`` (a function of time), in the symbols of the state."""
    t_ = sysm.x_g.args[0]
    return [_to_symbols(X[i].diff(t_, 2), sysm, vg) for i in range(2)]


def block_accelerations(sysm: System, vg) -> list:
    """Horizontal absolute accelerations of the top's centre and of ``G``, affine in ``ddq`` (top first)."""
    horizontal = [_absolute_acceleration(X, sysm, vg)[0] for X in (sysm.top, sysm.bodies[0][2])]
    return [c for a in horizontal for c in affine_in_accelerations(a, sysm)]


def base_reaction(sysm: System, vg) -> list:
    """``V_b``, ``N_b`` and ``M_b`` of :class:`Equations`, each affine in ``ddq``.

    The ground's reaction is the only force on the block and its bodies besides the
    weights (the forces between them cancel in pairs along common lines of action):
    its resultant is ``sum m (a + g e_y)`` and its moment about the centre of the
    base ``O`` (fixed to the ground) is ``sum (X - O) x m (a + g e_y) + I alpha`` (Newton
    and Euler for each body, summed). ``M_b`` is minus that moment: the moment the
    block transmits to the ground, which tips it about ``A`` when positive.
    """
    t_ = sysm.x_g.args[0]
    g = _gravity(sysm)
    shear, normal, moment = sp.Integer(0), sp.Integer(0), sp.Integer(0)
    for mass, inertia, X, angle in sysm.bodies:
        a = _absolute_acceleration(X, sysm, vg)
        force = (mass * a[0], mass * (a[1] + g))
        r = [_to_symbols(c, sysm, vg) for c in _relative(X, sysm)]
        alpha = _to_symbols((sysm.qt[0] + angle).diff(t_, 2), sysm, vg)
        shear += force[0]
        normal += force[1]
        moment += r[0] * force[1] - r[1] * force[0] + inertia * alpha
    return [c for e in still([shear, normal, -moment]) for c in affine_in_accelerations(e, sysm)]


def element_forces(sysm: System, vg) -> list:
    """Per attached coordinate, ``dV_e/dq + dD/ddq``: the force of its elements on the block along it."""
    t_ = sysm.x_g.args[0]
    g = _gravity(sysm)
    weights = sum((mass * g * X[1] for mass, _, X, _ in sysm.bodies), sp.Integer(0))
    elastic = sysm.V - weights
    out = []
    for f in sysm.qt[1:]:
        out.append(_reduce(_to_symbols(elastic.diff(f) + sysm.D.diff(f.diff(t_)), sysm, vg)))
    return out


def _quiet(stage: str) -> None:
    """The default ``stage`` of :func:`derive`: nothing is told."""


def equations_of_motion(sysm: System, E: list) -> tuple:
    """The mass matrix and forcing of the rocking phase, ``M(q) ddq = forcing``, from the residuals ``E`` of
    Lagrange's equations (:func:`lagrange`).

    Raises
    ------
    SpecError
        When the equations are not linear in the accelerations.
    """
    n = len(sysm.q)
    Mm = sp.Matrix(n, n, lambda i, j: _reduce(sp.diff(E[i], sysm.ddq[j])))
    f = sp.Matrix([_reduce(-(E[i] - sum(Mm[i, j] * sysm.ddq[j] for j in range(n)))) for i in range(n)])
    if any(f[i].has(*sysm.ddq) for i in range(n)):
        raise SpecError("the equations are not linear in the accelerations")
    return Mm, f


def contact_and_uplift(sysm: System, Mm: sp.Matrix, f: sp.Matrix) -> tuple:
    """The accelerations in full contact (``ddtheta = 0``) and the uplift function about the pivot ``s``."""
    at_contact = {sysm.q[0]: 0, sysm.dq[0]: 0}
    D0 = Mm[1:, 1:].subs(at_contact)
    f0 = f.subs(at_contact)
    contact = [sp.Integer(0)]
    if len(sysm.q) > 1:
        contact += list(D0.LUsolve(f0[1:, 0]).applyfunc(sp.cancel))
        coupling = D0.LUsolve(Mm[1:, 0].subs(at_contact)).applyfunc(sp.cancel)
        reaction = (coupling.T * f0[1:, 0])[0] - f0[0]
    else:
        reaction = -f0[0]
    return contact, _reduce(-s * reaction)


def energy_and_power(sysm: System, vg) -> tuple:
    """The mechanical energy in the ground frame and its rate along solutions.

    The rate is the dissipation plus the power of the inertial ground force
    ``-(mass) (ddx_g, ddy_g)`` on the velocities relative to the ground.
    """
    T_rel = _to_symbols(_at_rest_ground(sysm.T, sysm), sysm, vg).subs(vg, 0)
    V = _to_symbols(_at_rest_ground(sysm.V, sysm), sysm, vg)
    energy = _reduce(T_rel + V)
    momentum = sp.zeros(2, 1)
    for mass, _, X, _ in sysm.bodies:
        momentum += mass * _relative(X, sysm).diff(sysm.x_g.args[0])
    momentum = [_to_symbols(p, sysm, vg) for p in momentum]
    D = _to_symbols(sysm.D, sysm, vg)
    return energy, _reduce(-2 * D - ag * momentum[0] - agy * momentum[1])


def derive(spec: Spec, options: dict | None = None, stage=_quiet) -> Equations:
    """Derive every expression of ``spec`` under ``options``.

    Parameters
    ----------
    spec : Spec
        The model.
    options : dict, optional
        ``impact``: ``"spec"`` (the spec's law per coordinate, default),
        ``"momentum"`` or ``"velocity"`` for all coordinates; ``inertia``:
        ``"free"`` (``I_G`` is a parameter, default) or ``"homogeneous"``.
    stage : callable, optional
        Called with the name of each stage of the derivation as it begins
        (``"energies"``, ``"equations of motion"``, ...): a watchdog's clock
        (:mod:`rocking.derive.watchdog`).
    """
    opts = resolve_options(spec, options)
    stage("energies")
    sysm = build_system(spec, opts["inertia"])
    stage("equations of motion")
    residuals = lagrange(sysm)
    Mm, f = equations_of_motion(sysm, still(residuals))
    stage("rocking accelerations")
    rocking = _schur_solve(Mm, f, finite=False)
    stage("contact and uplift")
    contact, uplift = contact_and_uplift(sysm, Mm, f)
    stage("energy and power")
    vg = sp.Symbol("vg", real=True)
    energy, power = energy_and_power(sysm, vg)
    weights = _weights_moment(sysm)
    gaps, forces, contacts = stop_gaps_and_forces(sysm, vg)
    approaches = stop_approaches(sysm, vg)
    memory = stop_memories(sysm, approaches)
    on = stop_indicators(sysm, contacts, memory)
    # Forces read at a state in its own pushing, with the memory of the regime given (a contact's v_in).
    pushing = stop_indicators(sysm, contacts, {})

    def where(expr):
        """``expr`` with its bumpers' terms in their penetrations, the indicators kept: the regime is an input."""
        return clip_pad_powers(in_penetrations(expr, sysm, vg)) if on else expr

    stage("least potentials")
    least, stroke = least_potentials(sysm, energy, spec, opts["impact_laws"])
    stage("uplift energy")
    least_uplift = uplift_energy(sysm, energy, uplift)
    stage("impact map")
    impact = impact_map(sysm, opts["impact_laws"])
    stage("stop regimes")
    # The bumpers' terms of every expression a runtime reads, in their penetrations (in_penetrations).
    regimes = [f.applyfunc(where), [where(a) for a in rocking], [where(a) for a in contact]]
    regimes += [where(e) for e in (uplift, energy, power)]
    # Not in the inner loop of a runtime, and read at states of either regime (rule 6): from the state.
    stop_forces = [where(force).xreplace(pushing) for force in forces]
    stage("reactions")
    return Equations(
        uplift_energy=least_uplift,
        least_potential=least,
        least_stroke_potential=stroke,
        system=sysm,
        options=opts,
        mass_matrix=Mm,
        forcing=regimes[0],
        rocking_accel=regimes[1],
        contact_accel=regimes[2],
        uplift=regimes[3],
        impact=impact,
        energy=regimes[4],
        power=regimes[5],
        critical_angle=critical_angle(*weights),
        critical_tangent=critical_tangent(*weights),
        stop_gaps=gaps,
        stop_forces=stop_forces,
        stop_contact=contacts,
        block_accelerations=block_accelerations(sysm, vg),
        base_reaction=base_reaction(sysm, vg),
        # As the bumpers' forces: read at the states of a recorded history, in their own regime.
        element_forces=[where(force).xreplace(pushing) for force in element_forces(sysm, vg)],
        stop_regime=[*on.values(), *memory.values()],
        stop_memory=tuple(memory),
        stop_approach=tuple(approaches),
        vertical=vertical_as_gravity(residuals, sysm),
    )
