"""Kinematics and energies of the block and its bodies, about either base corner.

Nothing here is an equation of motion: positions are written in the block
frame, rotated about the active pivot, and turned into kinetic energy,
potential energy and Rayleigh dissipation. ``rocking.derive.equations`` applies
Lagrange's equations to them.

The pivot is the symbol ``s``: ``+1`` rotates about the left corner ``A``,
``-1`` about the right corner ``A'`` (docs/model.md section 1). Positions are
absolute: the ground displacement ``(x_g(t), y_g(t))`` is added to every point, so
the ground acceleration enters through Lagrange's equations, not by hand.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .spec import BLOCK_PARAMETERS, INERTIA_OPTIONS, Spec, SpecError

t = sp.Symbol("t", real=True)
s = sp.Symbol("s", real=True)
#: Ground acceleration ``ddx_g`` once the derivation is done.
ag = sp.Symbol("ag", real=True)
#: Vertical ground acceleration ``ddy_g`` (> 0 up) once the derivation is done.
agy = sp.Symbol("agy", real=True)


@dataclass(frozen=True)
class System:
    """Symbols and energies of one model about the pivot ``s``.

    Attributes
    ----------
    q, dq, ddq : tuple of Symbol
        Coordinates (``theta`` first), velocities and accelerations.
    params : tuple of Symbol
        Parameters in argument order.
    T, V, D : Expr
        Kinetic energy (absolute velocities, functions of ``t``), potential
        energy and Rayleigh dissipation function, written with the
        time functions ``qt``.
    qt : tuple of Function
        The coordinates as functions of time, used by Lagrange's equations.
    x_g, y_g : Function
        Ground displacement, horizontal and vertical (> 0 up).
    bodies : list of (mass, inertia, position, angle)
        All bodies including the block (first, at its centroid ``G``), positions
        absolute (with ``x_g`` and ``y_g``).
    top : Matrix
        Absolute position of the centre of the block's top side, block frame ``(0, H)``.
    stops : tuple of (Symbol, Expr, Expr, Expr, int, Pad)
        One per side of every end stop: its indicator ``on`` (1 while the
        bumper acts, 0 elsewhere; a symbol while deriving), the penetration
        ``delta`` (written with the time functions ``qt``; the bumper acts
        while it is > 0), the bumper's stiffness and damping, the index
        of its stop in the spec, and its contact law (:class:`Pad`).
    """

    q: tuple
    dq: tuple
    ddq: tuple
    params: tuple
    qt: tuple
    x_g: sp.Expr
    y_g: sp.Expr
    T: sp.Expr
    V: sp.Expr
    D: sp.Expr
    bodies: tuple
    top: sp.Matrix
    stops: tuple = ()


class pad_power(sp.Function):  # noqa: N801 - a SymPy function, named as SymPy's are
    """``max(delta, 0)^p``: a Hunt-Crossley pad's power of its penetration.

    A function of its own, not ``Pow``: SymPy differentiates ``delta^(n+1)`` into
    ``(n+1) delta^(n+1) / delta``, which is 0/0 at contact; this one's derivative is
    ``p max(delta, 0)^(p-1)``, and it is written out as ``Max(delta, 0)**p`` only
    for the printers (:func:`rocking.derive.equations.clip_pad_powers`).
    """

    nargs = 2

    def fdiff(self, argindex=1):
        """``d/d delta``; the exponent is a parameter, never differentiated by Lagrange's equations."""
        delta, p = self.args
        if argindex != 1:
            raise sp.ArgumentIndexError(self, argindex)
        return p * pad_power(delta, p - 1)


@dataclass(frozen=True)
class Pad:
    """The contact law of one stop side (docs/model.md section 11).

    Attributes
    ----------
    law : str
        ``"kelvin-voigt"`` or ``"hunt-crossley"``.
    exponent, damping_factor : Expr
        The Hunt-Crossley law's ``n`` and ``chi`` (1 and 0 for Kelvin-Voigt): ``chi`` is the
        damping factor of a restitution ``e_b``, ``chi(e_b)``, which the runtime solves for
        (:func:`rocking.model.params.hunt_crossley_damping`; no closed form to derive).
    approach : Symbol
        The side's memory ``v_in``, the approach speed at the start of the contact,
        an input like its indicator (``_vin<i>``).
    approach_floor : float
        The least ``v_in`` a runtime records.
    """

    law: str
    exponent: sp.Expr
    damping_factor: sp.Expr
    approach: sp.Symbol
    approach_floor: float

    @property
    def hunt_crossley(self) -> bool:
        """Whether the pad follows the Hunt-Crossley law."""
        return self.law == "hunt-crossley"

    def potential(self, k, delta):
        """The pad's strain energy at the penetration ``delta`` while it pushes."""
        n = self.exponent
        return k * pad_power(delta, n + 1) / (n + 1) if self.hunt_crossley else k * delta**2 / 2

    def dissipation(self, k, c, delta, rate):
        """Its Rayleigh dissipation at ``delta`` and ``rate = ddelta`` while it pushes."""
        if self.hunt_crossley:
            return k * pad_power(delta, self.exponent) * self.damping_factor * rate**2 / (2 * self.approach)
        return c * rate**2 / 2

    def push(self, k, c, delta, rate):
        """The bracket whose sign says whether the pad pushes, and the force it pushes with (where ``delta > 0``).

        Kelvin-Voigt: both ``k delta + c ddelta``. Hunt-Crossley: ``v_in + chi ddelta``
        (a speed, the sign of ``1 + chi ddelta / v_in``) and ``k delta^n (1 + chi ddelta / v_in)``.
        """
        if self.hunt_crossley:
            force = k * pad_power(delta, self.exponent) * (1 + self.damping_factor * rate / self.approach)
            return self.approach + self.damping_factor * rate, force
        return k * delta + c * rate, k * delta + c * rate


def rotation(angle):
    """Counter-clockwise rotation matrix."""
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


def block_symbols(inertia: str):
    """The block's parameter symbols; ``I_G`` is an expression when homogeneous."""
    if inertia not in INERTIA_OPTIONS:
        raise SpecError(f"option inertia: unknown value {inertia!r}; choose one of {', '.join(INERTIA_OPTIONS)}")
    sym = {name: sp.Symbol(name, real=True) for name, *_ in BLOCK_PARAMETERS}
    I_G = sym["I_G"]
    if inertia == "homogeneous":
        I_G = sym["M"] * (sym["B"] ** 2 + sym["H"] ** 2) / 12
        del sym["I_G"]
    return sym, I_G


def build_system(spec: Spec, inertia: str = "free") -> System:
    """Energies of ``spec`` rotating about the pivot ``s``.

    Parameters
    ----------
    spec : Spec
        The model.
    inertia : {"free", "homogeneous"}
        ``I_G`` as a parameter, or the homogeneous rectangle's value.
    """
    block, I_G = block_symbols(inertia)
    own = {p.name: sp.Symbol(p.name, real=True) for p in spec.parameters}
    names = ("theta",) + spec.coordinates
    q = tuple(sp.Symbol(n, real=True) for n in names)
    dq = tuple(sp.Symbol("d" + n, real=True) for n in names)
    ddq = tuple(sp.Symbol("dd" + n, real=True) for n in names)
    qt = tuple(sp.Function(n, real=True)(t) for n in names)
    x_g = sp.Function("x_g", real=True)(t)
    y_g = sp.Function("y_g", real=True)(t)
    to_time = dict(zip(q, qt))

    M, B, H, e, g = (block[k] for k in ("M", "B", "H", "e", "g"))
    theta = qt[0]
    corner = sp.Matrix([-s * B / 2, 0])
    rot = rotation(theta)

    def place(r):
        """Ground-frame position of a block-frame point while rocking about ``s``."""
        return corner + rot * (sp.Matrix(r) - corner) + sp.Matrix([x_g, y_g])

    bodies = [(M, I_G, place((e, H / 2)), sp.Integer(0))]
    for b in spec.bodies:
        r = [sp.sympify(c).subs(to_time) for c in b.position]
        bodies.append((b.mass, b.inertia, place(r), b.angle.subs(to_time)))

    T = sp.Integer(0)
    V = sp.Integer(0)
    for mass, inertia_b, X, angle in bodies:
        v = X.diff(t)
        omega = (theta + angle).diff(t)
        T += mass * (v[0] ** 2 + v[1] ** 2) / 2 + inertia_b * omega**2 / 2
        V += mass * g * X[1]
    for el in spec.springs:
        V += el.coefficient * el.measure.subs(to_time) ** 2 / 2
    D = sp.Integer(0)
    for el in spec.dashpots:
        D += el.coefficient * el.measure.subs(to_time).diff(t) ** 2 / 2
    sides = [
        (sigma * stop.travel.subs(to_time) - stop.gap, stop.stiffness, stop.damping, j, stop)
        for j, stop in enumerate(spec.stops)
        for sigma in stop.sides
    ]
    # A bumper acts beyond its gap only, while it pushes (docs/model.md section 11). Its potential has a
    # continuous derivative at delta = 0, so Lagrange's equations hold with the indicator "on" held
    # constant: the equations stay polynomial in it, and each region of the guide is a plain model.
    # A Hunt-Crossley pad's memory v_in is held constant likewise: it changes only at a contact's start.
    stops = tuple(
        (
            sp.Symbol(f"_on{i}", real=True),
            delta,
            k,
            c,
            j,
            Pad(
                stop.law, stop.exponent, stop.damping_factor, sp.Symbol(f"_vin{i}", positive=True), stop.approach_floor
            ),
        )
        for i, (delta, k, c, j, stop) in enumerate(sides)
    )
    for on, delta, stiffness, damping, _, pad in stops:
        V += on * pad.potential(stiffness, delta)
        D += on * pad.dissipation(stiffness, damping, delta, delta.diff(t))

    params = tuple(block.values()) + tuple(own.values())
    return System(q, dq, ddq, params, qt, x_g, y_g, T, V, D, tuple(bodies), place((0, H)), stops)


def coordinate_units(spec: Spec) -> dict[str, str]:
    """Unit of each coordinate, ``theta`` first: ``"rad"`` for an angle, ``"m"`` for a length.

    The positions are lengths, so a coordinate that enters them only through the
    arguments of trigonometric functions (or enters a body's angle) is an angle;
    any other enters a length linearly somewhere and is one.
    """
    units = {"theta": "rad"}
    positions = [sp.sympify(c) for b in spec.bodies for c in b.position]
    angles = [b.angle for b in spec.bodies]
    for name in spec.coordinates:
        q = sp.Symbol(name, real=True)
        trig = {f: sp.Dummy() for p in positions for f in p.atoms(sp.sin, sp.cos, sp.tan) if f.has(q)}
        outside = any(p.xreplace(trig).has(q) for p in positions)
        units[name] = "rad" if any(sp.sympify(a).has(q) for a in angles) or (trig and not outside) else "m"
    return units
