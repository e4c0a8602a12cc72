"""What an expression of a spec will cost the derivation, bounded before any of it starts.

A spec's expressions are short (:mod:`rocking.derive.expressions` bounds their
text), but a short text can still stand for an expansion the derivation never
finishes: ``sin(x)**40*cos(x)**40`` is 21 characters, and its velocity squared,
differentiated again and expanded (Lagrange's equations, then the bounds of
:mod:`rocking.derive.equations`) runs for many minutes. The work grows as a
power of three measures of each expression, read off its tree without
expanding it:

``degree``
    Its total degree as a polynomial in the coordinates and in the functions
    of them (``sin(x)``, ``sqrt(1 + x**2)``, each a variable of degree 1, or of
    its argument's degree when higher). Every derivative keeps it, and the
    kinetic energy squares it.
``terms``
    How many terms its expansion has at most (a power of a sum counted as its
    multinomial expansion, a function as one term of its argument's size).
``nesting``
    How deep functions of the coordinates are nested in one another
    (``exp(exp(x))`` is 2): each level multiplies the terms of every
    derivative by the chain rule.
``argument``
    The highest degree of what a function of the coordinates, or a fractional
    power, is taken of (``sin(x)`` 1, ``sqrt(1 + x**2)`` 2): the derivatives
    of ``1/sqrt(1 + x**2)`` bring powers of its argument into every
    denominator, which the later stages (the common subexpressions, the LaTeX
    printer) are slow to get through. SymPy writes ``sin(atan(x))`` so
    (``x/sqrt(x**2 + 1)``), before it is measured.

:func:`check_spec_cost` refuses an entry of a spec over :data:`LIMITS`, before
anything is derived; what passes but is still slow is stopped by the limit of
CPU time of each stage (:mod:`rocking.derive.watchdog`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from .names import SpecError, quote


@dataclass(frozen=True)
class Cost:
    """The three measures of an expression (module docstring)."""

    degree: int
    terms: int
    nesting: int
    argument: int = 0


#: Largest ``degree``, ``terms``, ``nesting`` and ``argument`` of an entry of a spec; every shipped model is
#: within degree 2, 2 terms, nesting 1 and argument 1. Measured on the omd spec with its position x changed, in
#: CPU time (``python bench/derive_cost.py``; docs/variants.md, "Bounded derivations"): ``x + h*sin(x)**2*cos(x)**2``
#: (degree 4) derives in 6.1 s, ``x + h*(sin(x) + cos(x))**4`` (degree 4, 6 terms) in 14.6 s; of degree 6,
#: ``x + h*(sin(x) + cos(x))**6`` takes 35.2 s, and ``x + h*sin(atan(x))`` (argument 2) 90.9 s, most of it in its
#: LaTeX stage; issue 23's spec (degree 80) did not derive in 400 s of the clock. What passes but is still slow is
#: stopped by the limit of CPU time of each stage.
LIMITS = Cost(degree=4, terms=16, nesting=1, argument=1)

#: Why each measure is bounded, in a message.
_WHAT = {
    "degree": "degree in the coordinates and their functions",
    "terms": "number of terms once expanded",
    "nesting": "nesting of functions of the coordinates",
    "argument": "degree of what a function or a fractional power of the coordinates is taken of",
}

#: Any count above this is reported as this: a bound, not a number to compute exactly.
_CAP = 10**9


def _monomials(terms: int, power: int) -> int:
    """Terms of ``(a_1 + ... + a_terms)**power`` expanded: the monomials of degree ``power`` in ``terms`` variables."""
    if terms <= 1:
        return 1
    return min(math.comb(terms + power - 1, power), _CAP)


def _power(base: Cost, exponent: Cost, integer: int | None, varies: bool) -> Cost:
    """Cost of ``base**exponent``: a multinomial for an ``integer`` exponent, a new function of both otherwise."""
    if integer is not None:
        n = abs(integer)
        return Cost(min(base.degree * n, _CAP), _monomials(base.terms, n), base.nesting, base.argument)
    if not varies:
        return Cost(0, 1, 0)
    # d(b**e)/dt = b**e (e' log(b) + e b'/b): the exponent's terms count only when it moves.
    terms = base.terms + (exponent.terms if exponent.degree else 0)
    return Cost(
        max(1, base.degree, exponent.degree),
        min(terms, _CAP),
        1 + max(base.nesting, exponent.nesting),
        max(base.argument, exponent.argument, base.degree, exponent.degree),
    )


def expression_cost(expr: sp.Expr, varying: frozenset) -> Cost:
    """The :class:`Cost` of ``expr``, where ``varying`` are the symbols that move (the coordinates).

    Parameters
    ----------
    expr : Expr
        An expression of a spec, as :func:`rocking.derive.expressions.parse_expression` built it.
    varying : frozenset of Symbol
        The coordinates: what time derivatives act on.
    """
    varies = bool(expr.free_symbols & varying)
    if expr.is_Atom:
        return Cost(int(varies), 1, 0)
    if expr.is_Pow:
        integer = int(expr.exp) if expr.exp.is_Integer else None
        return _power(expression_cost(expr.base, varying), expression_cost(expr.exp, varying), integer, varies)
    parts = [expression_cost(a, varying) for a in expr.args]
    argument = max(p.argument for p in parts)
    if expr.is_Add:
        return Cost(
            max(p.degree for p in parts),
            min(sum(p.terms for p in parts), _CAP),
            max(p.nesting for p in parts),
            argument,
        )
    if expr.is_Mul:
        return Cost(
            min(sum(p.degree for p in parts), _CAP),
            min(math.prod(p.terms for p in parts), _CAP),
            max(p.nesting for p in parts),
            argument,
        )
    if not varies:  # a function of the parameters alone: one constant of a run
        return Cost(0, 1, 0)
    # A function of the coordinates: a new variable, whose derivative brings its argument's along (chain rule).
    return Cost(
        max(1, *(p.degree for p in parts)),
        min(sum(p.terms for p in parts), _CAP),
        1 + max(p.nesting for p in parts),
        max(argument, *(p.degree for p in parts)),
    )


def over_limit(cost: Cost, limits: Cost = LIMITS) -> str | None:
    """The first measure of ``cost`` over ``limits`` (``its <measure> is <value>, at most <limit> allowed``) or None."""
    for name, what in _WHAT.items():
        value, limit = getattr(cost, name), getattr(limits, name)
        if value > limit:
            shown = f"over {_CAP}" if value >= _CAP else str(value)
            return f"its {what} is {shown}, at most {limit} allowed"
    return None


def spec_entries(spec) -> list[tuple[str, sp.Expr]]:
    """Every expression of ``spec`` with where it is, named as the spec's checks name it."""
    entries = []
    for b in spec.bodies:
        fields = {"mass": b.mass, "position x": b.position[0], "position y": b.position[1]}
        fields.update({"inertia": b.inertia, "angle": b.angle})
        entries += [(f"body {b.name!r} {key}", expr) for key, expr in fields.items()]
    for kind, elements, keys in (
        ("spring", spec.springs, "stiffness stretch"),
        ("dashpot", spec.dashpots, "damping rate_of"),
    ):
        coefficient, measure = keys.split()
        for el in elements:
            entries += [(f"{kind} {el.name!r} {coefficient}", el.coefficient)]
            entries += [(f"{kind} {el.name!r} {measure}", el.measure)]
    for stop in spec.stops:
        for key in ("travel", "gap", "stiffness", "damping", "exponent", "damping_factor"):
            entries.append((f"stop {stop.name!r} {key}", getattr(stop, key)))
    return entries


def _varying(spec) -> frozenset:
    """The coordinates of ``spec`` as the symbols its expressions hold."""
    return frozenset(sp.Symbol(c, real=True) for c in spec.coordinates)


def check_spec_cost(spec, limits: Cost = LIMITS) -> None:
    """Refuse ``spec`` if one of its expressions is over ``limits`` (module docstring).

    Raises
    ------
    SpecError
        Naming the entry, quoting the expression, and the measure with its limit.
    """
    varying = _varying(spec)
    for where, expr in spec_entries(spec):
        excess = over_limit(expression_cost(expr, varying), limits)
        if excess:
            raise SpecError(
                f"{where}: {quote(str(expr))} is too costly to derive: {excess} "
                "(write it with lower powers, fewer terms and functions of functions)"
            )


def costliest_entry(spec) -> tuple[str, sp.Expr] | None:
    """The entry of ``spec`` of the highest cost (by degree, nesting, argument, then terms): the likely cause of a
    slow stage."""
    varying = _varying(spec)
    ranked = [(expression_cost(expr, varying), where, expr) for where, expr in spec_entries(spec)]
    if not ranked:
        return None
    cost, where, expr = max(ranked, key=lambda r: (r[0].degree, r[0].nesting, r[0].argument, r[0].terms))
    return where, expr
