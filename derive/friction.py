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
from .mechanics import ag
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
    """

    slide_accel: list
    contact_slide_accel: list
    slide_uplift: sp.Expr


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
    slide = [a.xreplace({ag: ag + ddu}) for a in rocking] + [ddu]
    held = {q[0]: 0, dq[0]: 0}
    contact = list(eq.contact_accel)
    ddu_c = _slip_acceleration(eq, contact, held)
    contact_slide = [a.xreplace({ag: ag + ddu_c}) for a in contact] + [ddu_c]
    return Sliding(slide, contact_slide, eq.uplift.xreplace({ag: ag + ddu_c}))
