"""The sliding phases of a floor with friction (docs/model.md section 15), from the derived equations.

The base's slip ``u`` relative to the ground moves the whole block and its bodies as the ground does: every
absolute position gains ``u`` where it holds ``x_g``. Lagrange's equations of the other coordinates are
therefore those already derived with ``ddx_g`` replaced by ``ddx_g + ddu``, and the equation of ``u`` is
Newton's law of the whole system along the floor, ``V_b = F``: the base shear of
:func:`~rocking.derive.equations.base_reaction` (the ground's horizontal force) at the accelerations of the
phase, equal to the friction force ``F``. While the contact slides, Coulomb's law closes the system,
``F = -mu_k N sign(du)``, with ``N = N_b`` the ground's normal force at the same accelerations; ``V_b`` and
``N_b`` are affine in ``ddu``, so one linear equation gives it. While it sticks, ``ddu = 0`` and
``(V_b, N_b)`` are the force the contact must hold, ``|V_b| <= mu_s N_b``.

The kinetic coefficient and the slip's direction enter as one symbol, :data:`mu_slip` ``= mu_k sign(du)``:
the friction force on the block is ``-mu_slip N``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .equations import Equations
from .mechanics import ag, s
from .spec import SpecError

#: ``mu_k sign(du)``: the kinetic friction coefficient signed by the slip's direction.
mu_slip = sp.Symbol("mu_slip", real=True)
#: The slip's acceleration while it is solved for.
_ddu = sp.Symbol("ddu", real=True)


@dataclass(frozen=True)
class Sliding:
    """The accelerations of the sliding phases.

    Attributes
    ----------
    slide_accel : list of Expr
        Rocking about ``s`` while the pivot slides: ``ddq`` (``ddtheta`` first), then ``ddu``.
    contact_slide_accel : list of Expr
        Full contact while the base slides: ``ddq`` (``ddtheta = 0``), then ``ddu``.
    slide_uplift : Expr
        The uplift margin of section 5 about ``s`` while the base slides in full contact.
    slide_normal, contact_slide_normal : Expr
        The floor's normal force ``N`` on the sliding contact, rocking and in full contact (the friction force
        is ``-mu_slip N``).
    """

    slide_accel: list
    contact_slide_accel: list
    slide_uplift: sp.Expr
    slide_normal: sp.Expr
    contact_slide_normal: sp.Expr


def _reaction(eq: Equations, which: int, ddq: list) -> sp.Expr:
    """``V_b`` (``which = 0``) or ``N_b`` (1) of :attr:`Equations.base_reaction` at the accelerations ``ddq``."""
    n = len(eq.system.q)
    free, *coefficients = eq.base_reaction[which * (n + 1) : (which + 1) * (n + 1)]
    return free + sum((c * a for c, a in zip(coefficients, ddq)), sp.Integer(0))


def _slip_acceleration(eq: Equations, ddq: list, at: dict) -> sp.Expr:
    """``ddu`` from ``V_b + mu_slip N_b = 0`` with the frame accelerated by ``ddx_g + ddu``.

    ``ddq`` are the phase's accelerations at the ground acceleration ``ag``; ``at`` fixes coordinates the phase
    holds (``theta = dtheta = 0`` in full contact).

    Raises
    ------
    SpecError
        When the balance is not affine in ``ddu`` (it is for every model built from positions).
    """
    # The reactions and the accelerations hold ``ag`` alike: one substitution moves the whole frame.
    balance = (_reaction(eq, 0, ddq) + mu_slip * _reaction(eq, 1, ddq)).subs(at)
    balance = balance.xreplace({ag: ag + _ddu})
    slope = balance.diff(_ddu)
    if slope.has(_ddu):
        raise SpecError("the floor's force balance is not affine in the slip's acceleration")
    return -balance.subs(_ddu, 0) / slope


def sliding(eq: Equations) -> Sliding:
    """The sliding phases of the derived model ``eq``.

    Parameters
    ----------
    eq : Equations
        The derived model (its ``rocking_accel``, ``contact_accel``, ``uplift`` and ``base_reaction``).
    """
    q, dq = eq.system.q, eq.system.dq
    rocking = list(eq.rocking_accel)
    ddu = _slip_acceleration(eq, rocking, {})
    slide = [a.xreplace({ag: ag + ddu}) for a in rocking]
    held = {q[0]: 0, dq[0]: 0}
    contact = list(eq.contact_accel)
    ddu_c = _slip_acceleration(eq, contact, held)
    contact_slide = [a.xreplace({ag: ag + ddu_c}) for a in contact]
    normal = _reaction(eq, 1, rocking).xreplace({ag: ag + ddu})
    normal_c = _reaction(eq, 1, contact).subs(held).xreplace({ag: ag + ddu_c})
    return Sliding(slide + [ddu], contact_slide + [ddu_c], eq.uplift.xreplace({ag: ag + ddu_c}), normal, normal_c)


@dataclass(frozen=True)
class FrictionImpact:
    """The impact of the corner ``-s`` at ``theta = 0`` on a floor with friction (docs/model.md section 15).

    Each list holds the velocities after the impact (``dq`` with ``dtheta`` first, then the slip speed ``du`` of the
    new contact), then the impulses of the floor on the corner, tangential ``P_t`` and normal ``P_n``; they are
    written with the velocities before the impact, ``dq`` and :data:`du_before` (the old pivot's slip speed).

    Attributes
    ----------
    stick : list of Expr
        The corner sticks (``du = 0`` after): valid while ``|P_t| <= mu_s P_n``.
    slide : list of Expr
        The corner slides through the impact, ``P_t = -mu_slip P_n``.
    """

    stick: list
    slide: list


#: The old pivot's slip speed before an impact.
du_before = sp.Symbol("du", real=True)


def _generalised_mass_matrix(eq: Equations) -> tuple:
    """The mass matrix of ``(theta, u, v, q[1:])`` at ``theta = 0``, the pivot's slip ``u`` and lift ``v`` added."""
    sysm = eq.system
    t_ = sysm.x_g.args[0]
    u_t, v_t = sp.Function("u", real=True)(t_), sp.Function("v", real=True)(t_)
    dw = sp.symbols("_dtheta _du _dv", real=True) + tuple(sp.Symbol("_" + str(d), real=True) for d in sysm.dq[1:])
    rates = [sysm.qt[0].diff(t_), u_t.diff(t_), v_t.diff(t_), *(f.diff(t_) for f in sysm.qt[1:])]
    T = sp.Integer(0)
    for mass, inertia, X, angle in sysm.bodies:
        moved = (X - sp.Matrix([sysm.x_g, sysm.y_g]) + sp.Matrix([u_t, v_t])).diff(t_)
        omega = (sysm.qt[0] + angle).diff(t_)
        T += mass * (moved[0] ** 2 + moved[1] ** 2) / 2 + inertia * omega**2 / 2
    T = T.xreplace(dict(zip(rates, dw))).xreplace(dict(zip(sysm.qt, sysm.q))).subs(sysm.q[0], 0)
    return sp.Matrix(len(dw), len(dw), lambda i, j: sp.expand(T.diff(dw[i], dw[j]))), dw


def friction_impact(eq: Equations) -> FrictionImpact:
    """The impact map with friction, from the impulsive form of Lagrange's equations.

    With the coordinates ``w = (theta, u, v, q[1:])`` (``u``, ``v``: the old pivot's horizontal and vertical
    displacement), ``M (w+ - w-) = J^T (P_t, P_n)``, ``J`` the Jacobian of the new corner's position: at
    ``theta = 0`` its rows are ``(0, 1, 0, 0...)`` and ``(s B, 0, 1, 0...)``. No impulse acts along an attached
    coordinate (the momentum law of section 6) or at the old pivot, which leaves the floor. Before the impact
    ``dv = 0`` and ``du`` is :data:`du_before`; after it the corner's normal velocity is 0 (plastic), and either
    its slip is 0 (``stick``) or ``P_t = -mu_slip P_n`` (``slide``). At ``theta = 0`` every point of the base has
    the slip speed ``du``: the new contact's after the impact.
    """
    sysm = eq.system
    B = sysm.params[[p.name for p in sysm.params].index("B")]
    Mw, _ = _generalised_mass_matrix(eq)
    n = Mw.shape[0]
    before = sp.Matrix([sysm.dq[0], du_before, 0, *sysm.dq[1:]])
    after = sp.Matrix(sp.symbols(f"_w0:{n}", real=True))
    P_t, P_n = sp.symbols("_P_t _P_n", real=True)
    J = sp.zeros(2, n)
    J[0, 1], J[1, 0], J[1, 2] = 1, s * B, 1
    momentum = list(Mw * (after - before) - J.T * sp.Matrix([P_t, P_n]))
    normal = (J[1, :] * after)[0]
    unknowns = [*after, P_t, P_n]
    out = []
    for closure in ((J[0, :] * after)[0], P_t + mu_slip * P_n):
        solved = sp.solve([*momentum, normal, closure], unknowns, dict=True)
        if len(solved) != 1:
            raise SpecError("the impact with friction has no unique solution")
        w = solved[0]
        velocities = [w[after[0]], *(w[a] for a in after[3:]), w[after[1]]]
        out.append([sp.cancel(v.subs(s**2, 1)) for v in (*velocities, w[P_t], w[P_n])])
    return FrictionImpact(*out)


@dataclass(frozen=True)
class Contact:
    """What the floor must hold while the contact sticks, and the slip's share of the energy.

    Attributes
    ----------
    stick_force : list of Expr
        Rocking about ``s`` with the pivot held: the tangential force ``F = V_b`` and the normal force
        ``N = N_b`` of the floor on the block and its bodies (``|F| <= mu_s N`` keeps it).
    contact_stick_force : list of Expr
        The same in full contact (``theta = dtheta = 0``).
    slip_energy : Expr
        The kinetic energy the slip ``du`` (:data:`du_before`) adds to the energy relative to the ground:
        ``du P_x + m_total du^2 / 2``, ``P_x`` the horizontal momentum relative to the base.
    """

    stick_force: list
    contact_stick_force: list
    slip_energy: sp.Expr


def contact(eq: Equations) -> Contact:
    """The forces a sticking contact holds and the slip's energy, from the derived model ``eq``."""
    sysm = eq.system
    q, dq = sysm.q, sysm.dq
    held = {q[0]: 0, dq[0]: 0}
    rocking = [_reaction(eq, i, list(eq.rocking_accel)) for i in (0, 1)]
    full = [_reaction(eq, i, list(eq.contact_accel)).subs(held) for i in (0, 1)]
    t_ = sysm.x_g.args[0]
    energy = sp.Integer(0)
    for mass, _, X, _ in sysm.bodies:
        relative = (X[0] - sysm.x_g).diff(t_)
        energy += mass * (du_before * relative + du_before**2 / 2)
    rates = {f.diff(t_): d for f, d in zip(sysm.qt, dq)}
    energy = sp.expand(energy.xreplace(rates).xreplace(dict(zip(sysm.qt, q))))
    if energy.has(t_):
        raise SpecError("the slip's energy depends on the ground's motion")
    return Contact(rocking, full, energy)
