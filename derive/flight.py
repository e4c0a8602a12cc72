"""Flight and landing (docs/model.md section 16), from the derived equations.

In flight the block is free in the plane. Its state is the rocking state ``(theta, q[1:], dtheta, dq[1:])`` about
a reference corner ``s`` (the pivot of the phase it left) and the displacement ``(u, v)`` of that corner relative
to its place at rest on the ground (``u`` is the slip of section 15, ``v`` the corner's height above the floor).
Moving the corner by ``(u, v)`` moves the whole block and its bodies as the ground does: every absolute position
gains ``(u, v)`` where it holds ``(x_g, y_g)``. Lagrange's equations of ``r = (theta, q[1:])`` are therefore the
rocking equations with ``ddx_g`` replaced by ``ddx_g + ddu`` and ``g + ddy_g`` by ``g + ddy_g + ddv`` (the vertical
enters them only with gravity, :func:`~rocking.derive.equations.vertical_as_gravity`): the forcing's coefficients of
``ddx_g`` and ``g`` are the coupling ``-M_rc`` of ``r`` with ``c = (u, v)``. Those of ``u`` and ``v`` are Newton's
law of the whole system with no force on the corner, ``V_b = N_b = 0`` (the reactions of
:func:`~rocking.derive.equations.base_reaction` at the phase's accelerations), whose coefficients of ``ddr`` are the
same coupling (checked) and of ``ddc`` the total mass. As :mod:`.friction` closes the slip with one equation of the
reactions, flight closes ``(u, v)`` with two.

A landing is an impact at the reference corner (the back end first takes the corner that lands as the reference,
:func:`other_corner`): the impulsive form of Lagrange's equations with the coordinates ``w = (theta, u, v, q[1:])``,
``M_w (w+ - w-) = J^T (P_t, P_n)``. The corner is at ``(u, v)``: ``J`` selects ``u`` and ``v``, and no impulse acts
along ``theta`` or an attached coordinate (the momentum law of section 6). With ``r = (theta, q[1:])`` and
``c = (u, v)``, the rows of ``r`` give ``dr+ - dr- = -Y (dc+ - dc-)``, ``Y = M_rr^-1 M_rc``, and those of ``c``
the impulse ``P = K (dc+ - dc-)``, ``K = M_cc - M_rc^T Y`` the system's mass seen at the corner. The normal velocity
after is ``-e_n dv`` (``e_n = 0``: plastic); either the corner sticks (``du+ = 0``, valid while
``|P_t| <= mu_s P_n``) or it slides, ``P_t = -mu_slip P_n``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .equations import Equations, _gravity, _reduce, _schur_solve
from .friction import du_before, mu_slip
from .mechanics import ag, rotation, s
from .spec import SpecError

#: The reference corner's displacement relative to its place at rest: horizontal (the slip) and vertical (its height).
u = sp.Symbol("u", real=True)
v = sp.Symbol("v", real=True)
#: Their rates: ``du`` is the slip speed of section 15 (:data:`~rocking.derive.friction.du_before`).
du = du_before
dv = sp.Symbol("dv", real=True)
#: The normal coefficient of restitution of a landing: 0 plastic (the default), 1 elastic.
e_n = sp.Symbol("e_n", real=True)


def _parameter(eq: Equations, name: str) -> sp.Symbol:
    """The parameter symbol ``name`` of the model."""
    return eq.system.params[[p.name for p in eq.system.params].index(name)]


@dataclass(frozen=True)
class Frame:
    """The equations of the flying system, ``w = (theta, q[1:], u, v)`` split into ``r = (theta, q[1:])`` and
    ``c = (u, v)``: ``M_rr ddr + M_rc ddc = f_r`` and ``M_rc^T ddr + m ddc = -b``.

    Attributes
    ----------
    M_rr, f_r : Matrix
        The rocking mass matrix and forcing (:attr:`Equations.mass_matrix`, :attr:`Equations.forcing`).
    M_rc : Matrix
        Minus the forcing's coefficients of ``ddx_g`` and of ``g``: moving the frame by ``(ddu, ddv)`` adds
        ``-M_rc ddc`` to it. It is also the coupling of the kinetic energy (checked against the reactions).
    b : Matrix
        ``(V_b, N_b)`` at ``ddr = 0`` and ``ddc = 0``: the force the floor would need (:attr:`Equations.base_reaction`).
    m : Expr
        The total mass, the coefficient of ``ddu`` in ``V_b`` and of ``ddv`` in ``N_b``.
    """

    M_rr: sp.Matrix
    f_r: sp.Matrix
    M_rc: sp.Matrix
    b: sp.Matrix
    m: sp.Expr


def frame(eq: Equations) -> Frame:
    """The split equations of the flying system (:class:`Frame`), from the rocking equations and the reactions.

    Raises
    ------
    SpecError
        When the vertical ground acceleration enters the model otherwise than with gravity (the frame's vertical
        acceleration could not be added to it), or when the reactions do not hold the coupling of the forcing
        (the two must be the same kinetic energy's).
    """
    if not eq.vertical:
        raise SpecError("flight needs a model whose vertical ground acceleration enters only with gravity")
    g = _gravity(eq.system)
    n = len(eq.system.q)
    f_r = eq.forcing
    M_rc = sp.Matrix(n, 2, lambda i, j: _reduce(-f_r[i].diff((ag, g)[j])))
    rows = [eq.base_reaction[k * (n + 1) : (k + 1) * (n + 1)] for k in (0, 1)]
    masses = [_reduce(rows[0][0].diff(ag)), _reduce(rows[1][0].diff(g))]
    coupling = [_reduce(rows[k][1 + i] - M_rc[i, k]) for k in (0, 1) for i in range(n)]
    if masses[0] != masses[1] or any(coupling) or _reduce(rows[0][0].diff(g)) or _reduce(rows[1][0].diff(ag)):
        raise SpecError("the floor's reactions and the rocking forcing disagree on the flying system's inertia")
    return Frame(eq.mass_matrix, f_r, M_rc, sp.Matrix([rows[0][0], rows[1][0]]), masses[0])


def flight_accel(eq: Equations) -> list:
    """The accelerations in flight about the reference corner ``s``: ``ddq`` (``ddtheta`` first), ``ddu``, ``ddv``.

    Written, as the rocking accelerations, with ``g`` standing for the effective gravity ``g + ddy_g``. With
    ``ddc = -(b + M_rc^T ddr) / m`` from the rows of ``c``, those of ``r`` read
    ``(m M_rr - M_rc M_rc^T) ddr = m f_r + M_rc b``: the inertia about the system's centre of mass, solved by the
    Schur complement of ``theta`` so that ``ddtheta`` stays finite as the attached masses vanish.
    """
    fr = frame(eq)
    A = (fr.m * fr.M_rr - fr.M_rc * fr.M_rc.T).applyfunc(_reduce)
    rhs = (fr.m * fr.f_r + fr.M_rc * fr.b).applyfunc(_reduce)
    ddr = sp.Matrix(_schur_solve(A, rhs))
    ddc = -(fr.b + fr.M_rc.T * ddr) / fr.m
    return [*ddr, *ddc]


def other_corner(eq: Equations) -> list:
    """``(u, v, du, dv)`` of the corner ``-s`` from those of the corner ``s`` (:data:`u`, :data:`v`, ...).

    The corner ``-s`` is at ``(s B, 0)`` from the corner ``s`` in the block frame; its displacement is taken from its
    own place at rest, ``(s B / 2, 0)``. Its ``v`` is its height above the floor.
    """
    sysm = eq.system
    B = _parameter(eq, "B")
    t_ = sysm.x_g.args[0]
    theta_t, u_t, v_t = sysm.qt[0], sp.Function("u", real=True)(t_), sp.Function("v", real=True)(t_)
    corner = sp.Matrix([-s * B / 2 + u_t, v_t]) + rotation(theta_t) * sp.Matrix([s * B, 0])
    place = corner - sp.Matrix([s * B / 2, 0])
    rates = {theta_t.diff(t_): sysm.dq[0], u_t.diff(t_): du, v_t.diff(t_): dv}
    states = {theta_t: sysm.q[0], u_t: u, v_t: v}
    out = [*place, *place.diff(t_)]
    return [_reduce(o.xreplace(rates).xreplace(states)) for o in out]


def corner_heights(eq: Equations) -> list:
    """The heights above the floor of the corner ``s`` and of the corner ``-s`` (the landing events)."""
    return [v, other_corner(eq)[1]]


def flight_energy(eq: Equations) -> sp.Expr:
    """The mechanical energy in flight, relative to the ground: :attr:`Equations.energy` with the corner's velocity
    ``(du, dv)`` and height ``v`` added (the true ``g``, as the energy of section 2).

    The kinetic energy gains ``dc^T M_rc^T dr + m |dc|^2 / 2`` (the coupling of :class:`Frame`), the weights
    ``m g v``.
    """
    fr = frame(eq)
    dr = sp.Matrix(eq.system.dq)
    dc = sp.Matrix([du, dv])
    g = _gravity(eq.system)
    return _reduce(eq.energy + (dc.T * fr.M_rc.T * dr)[0] + fr.m * (du**2 + dv**2) / 2 + fr.m * g * v)


@dataclass(frozen=True)
class Landing:
    """The landing of the reference corner ``s``, at any tilt (docs/model.md section 16).

    Each list holds the velocities after the landing (``dq`` with ``dtheta`` first, then ``du`` and ``dv`` of the
    corner), then the floor's impulses on it, tangential ``P_t`` and normal ``P_n``; they are written with the
    velocities before it, ``dq``, :data:`du` and :data:`dv`, and the restitution :data:`e_n`.

    Attributes
    ----------
    stick : list of Expr
        The corner sticks (``du = 0`` after): valid while ``|P_t| <= mu_s P_n``.
    slide : list of Expr
        It slides through the landing, ``P_t = -mu_slip P_n``.
    """

    stick: list
    slide: list


def landing(eq: Equations) -> Landing:
    """The landing map with friction, from the impulsive form of Lagrange's equations (module docstring).

    ``M_rr``, ``M_rc`` and ``m`` are those of :class:`Frame`: the flying system's mass matrix.
    """
    fr = frame(eq)
    # Finite as the attached masses vanish: the same Schur complement as the rocking accelerations.
    Y = sp.Matrix.hstack(*(sp.Matrix(_schur_solve(fr.M_rr, fr.M_rc[:, k])) for k in range(2)))
    K = (fr.m * sp.eye(2) - fr.M_rc.T * Y).applyfunc(lambda x: _reduce(sp.together(x)))
    normal = -(1 + e_n) * dv
    tangential = {
        "stick": -du,
        "slide": -(K[0, 1] + mu_slip * K[1, 1]) * normal / (K[0, 0] + mu_slip * K[1, 0]),
    }
    out = []
    for law in ("stick", "slide"):
        jump = sp.Matrix([tangential[law], normal])
        dr = -Y * jump
        # The corner's velocities after are written as they are known: no sum that cancels to them.
        slip = sp.Integer(0) if law == "stick" else du + jump[0]
        after = [d + j for d, j in zip(eq.system.dq, dr)] + [slip, -e_n * dv]
        out.append([*after, *(K * jump)])
    return Landing(*out)


def flat_landing(eq: Equations) -> Landing:
    """The base landing flat on both corners at ``theta = 0`` (docs/model.md section 16).

    The floor's normal impulses ``P_s`` at the reference corner and ``P_o`` at the other, at ``(s B, 0)`` from it in
    the block frame (its vertical moves by ``s B`` per unit ``theta``: the generalised impulse on ``theta`` is
    ``s B P_o``), and the tangential ``P_t``. After it ``dtheta = 0`` (full contact), ``dv = -e_n dv`` and
    ``du = 0`` (``stick``) or ``P_t = -mu_slip (P_s + P_o)`` (``slide``); the attached coordinates take no impulse.
    Each list holds ``dq`` after (``dtheta`` first, 0), ``du``, ``dv``, then ``P_t``, ``P_s``, ``P_o``: a flat
    landing needs ``P_s >= 0`` and ``P_o >= 0`` (else one corner lands alone).
    """
    fr = frame(eq)
    sysm = eq.system
    B = _parameter(eq, "B")
    level = {sysm.q[0]: 0}
    M_rr, M_rc = fr.M_rr.subs(level), fr.M_rc.subs(level)
    d_theta = -sysm.dq[0]
    d_u = sp.Symbol("_du_jump", real=True)
    jump = sp.Matrix([d_u, -(1 + e_n) * dv])
    # The attached coordinates take no impulse: their rows give their jumps (finite as their masses vanish).
    if len(sysm.q) > 1:
        rest = -(M_rr[1:, 0] * d_theta + M_rc[1:, :] * jump)
        d_q = list(M_rr[1:, 1:].LUsolve(rest).applyfunc(sp.cancel))
    else:
        d_q = []
    d_r = sp.Matrix([d_theta, *d_q])
    moment = (M_rr[0, :] * d_r + M_rc[0, :] * jump)[0]
    impulse = M_rc.T * d_r + fr.m * jump
    closures = {"stick": -du, "slide": sp.solve(impulse[0] + mu_slip * impulse[1], d_u)}
    out = []
    for law in ("stick", "slide"):
        if law == "slide" and len(closures["slide"]) != 1:
            raise SpecError("the flat landing's sliding impulse has no unique solution")
        value = closures[law] if law == "stick" else closures[law][0]
        at = {d_u: value}
        P_o = s * moment.xreplace(at) / B
        P_n = impulse[1].xreplace(at)
        slip = sp.Integer(0) if law == "stick" else du + value
        after = [sp.Integer(0), *(d + j.xreplace(at) for d, j in zip(sysm.dq[1:], d_q)), slip, -e_n * dv]
        out.append(
            [sp.cancel(_reduce(x)) for x in after]
            + [sp.cancel(_reduce(x)) for x in (impulse[0].xreplace(at), P_n - P_o, P_o)]
        )
    return Landing(*out)
