"""From derived expressions to files: one model context, one generator per back end.

:func:`model_context` builds once per model what every back end needs: the
table of generated functions (:func:`model_functions`: name, meaning,
outputs), their arguments, and their expressions after common-subexpression
elimination and after hoisting the constants of a run. Each back end, a
:class:`Generator`, renders its files from that context alone and walks the
same table, so that the NumPy module, the C source and header, EQUATIONS.md
and manifest.json hold the same functions in the same order.

Every model exposes the same functions with the same arguments, so that a
runtime can drive any model from its manifest alone:

``name(s, <q...>, <dq...>, ag, agy, <params...>, stop_on=None)`` in NumPy, and
``prefix_name(double s, const double *y, double ag, double agy, const double *p[, double *out])``
in C, with ``y = (q, dq)``, ``ag`` and ``agy`` the horizontal and vertical ground
acceleration and ``p`` in manifest order. Arguments a function does not need are
accepted and ignored.

The functions whose equations hold the vertical ground acceleration only as the
effective gravity ``g + agy`` (:func:`rocking.derive.equations.vertical_as_gravity`)
are written with ``g`` standing for it: they read ``g + agy`` where the parameter
``g`` goes, and their prepared C forms take the constants of a run prepared at that
gravity. A runtime without vertical motion computes exactly what it did before. A
model whose energies use ``g`` elsewhere is written at ``agy = 0`` (its manifest's
``vertical`` is false, and a runtime refuses vertical motion for it).

The regime of the end stops (per stop side, 1 while its bumper acts, else 0)
is an input like the pivot: ``stop_on`` in NumPy, ``on`` of
``prefix_prepare(s, on, p, cst)`` in C, so that within a regime the equations
are plain polynomial and rational code and its constants are hoisted with the
pivot's. Without it (NumPy's ``stop_on=None``, C's unprepared functions) a
function takes the regime of its state: each side acts where its contact
(``stop_contact``: beyond the gap, the pad pushing) is > 0.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import jinja2
import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.numpy import NumPyPrinter

from . import flight, friction
from .equations import EFFECTIVE_GRAVITY, Equations
from .mechanics import ag, agy, coordinate_units, s
from .names import escape_c_comment, escape_markdown, escape_python_doc
from .spec import BLOCK_PARAMETERS, Parameter

TEMPLATES = Path(__file__).parent / "templates"
#: Version of the layout of manifest.json and of the generated interface; also written into
#: ``rocking.generated`` (see build.py). 3: the regime of the stops is an input (``stop_on``, ``on``).
#: 4: the units of the state (``units``); block_accelerations, base_reaction and element_forces. 5: stop_contact,
#: the regime function of pads that only push. 6: the law of each stop side (``stops``), the regime's inputs
#: (``regime``: the indicators, then the memory v_in of each Hunt-Crossley side), stop_approach. 7: the vertical
#: ground acceleration ``agy`` after ``ag``; the functions that hold it as gravity read ``g + agy``.
#: 8: the functions of a floor with friction (``friction``), each function's own ``inputs`` after the shared ones.
#: 9: the functions of flight and landing (``flight``).
MANIFEST_FORMAT = 9


@dataclass(frozen=True)
class Function:
    """One generated function: what it computes and its outputs, in order.

    Attributes
    ----------
    name, doc : str
        Its name in every back end, and its meaning in one line.
    outputs : tuple of Expr
        The derived expressions, in the symbols of the arguments.
    labels : tuple of str
        What each output is, in code comments and docstrings (``""`` for a
        scalar function).
    symbols : tuple of Expr
        What each output is, as a SymPy quantity: EQUATIONS.md writes
        ``symbol = output``.
    in_run : bool
        Whether a simulator calls it while it integrates. The others (the loads of a
        recorded history) come last in the table, and their constants are prepared
        after and apart from those of a run's functions, which stay as they were.
    effective_gravity : bool
        Whether its outputs are written with ``g`` standing for ``g + agy``
        (:class:`~rocking.derive.equations.Equations`).
    inputs : tuple of Argument
        Its own arguments after every function's (the friction's ``mu_slip``, the slip speed ``du``; the flying
        corner's ``u``, ``v``, ``du``, ``dv`` and a landing's ``e_n``).
    hoisted : bool
        Whether the C back end splits it into a run's constants and the rest
        (:func:`prepare_run`). The functions of friction and of flight are not: they read the parameters and
        the regime of the stops directly, so that what a run without them prepares stays as it was.
    """

    name: str
    doc: str
    outputs: tuple
    labels: tuple
    symbols: tuple
    in_run: bool = True
    effective_gravity: bool = False
    inputs: tuple = ()
    hoisted: bool = True

    @property
    def scalar(self) -> bool:
        """Whether the function returns one value rather than filling ``out``."""
        return len(self.outputs) == 1 and self.labels == ("",)


def _scalar(name: str, doc: str, output, symbol) -> Function:
    """A function of one output, returned rather than written to ``out``."""
    return Function(name, doc, (output,), ("",), (symbol,))


def model_functions(eq: Equations, friction: bool = False, flies: bool = False) -> list[Function]:
    """The generated interface of a derived model, in a fixed order: the table every back end follows.

    ``friction``: the functions of a floor with friction (:func:`friction_functions`) come after the others;
    ``flies``: those of flight and landing (:func:`flight_functions`) last.
    """
    sysm = eq.system
    names = [str(q) for q in sysm.q]
    n = len(names)
    acc = tuple("dd" + q for q in names)
    M, f = sp.IndexedBase("M"), sp.IndexedBase("f")
    delta, force, contact = sp.IndexedBase("delta"), sp.IndexedBase("F_b"), sp.IndexedBase("contact")
    theta_cr = sp.Symbol("theta_cr", real=True)
    table = [
        Function(
            "mass_matrix",
            "Mass matrix of the rocking phase about the pivot s, row-major.",
            tuple(eq.mass_matrix[i, j] for i in range(n) for j in range(n)),
            tuple(f"M[{i},{j}]" for i in range(n) for j in range(n)),
            tuple(M[sysm.q[i], sysm.q[j]] for i in range(n) for j in range(n)),
        ),
        Function(
            "forcing",
            "Forcing of the rocking phase about the pivot s: mass_matrix @ ddq = forcing.",
            tuple(eq.forcing),
            tuple(f"f[{q}]" for q in names),
            tuple(f[q] for q in sysm.q),
        ),
        Function(
            "rocking_accel",
            "Accelerations while rocking about the pivot s (finite ddtheta as the attached masses vanish).",
            tuple(eq.rocking_accel),
            acc,
            tuple(sysm.ddq),
        ),
        Function(
            "contact_accel",
            "Accelerations in full contact (theta = dtheta = 0); ddtheta is 0 and s is ignored.",
            tuple(eq.contact_accel),
            acc,
            tuple(sysm.ddq),
        ),
        _scalar(
            "uplift",
            "Uplift function about the pivot s in full contact: the block leaves the ground when it turns positive.",
            eq.uplift,
            sp.Symbol("u_s", real=True),
        ),
        Function(
            "impact",
            "Velocities after an impact at theta = 0 that ends rocking about s (new pivot -s); ag and agy are ignored.",
            tuple(eq.impact),
            tuple("d" + q + "_plus" for q in names),
            tuple(_after_impact(d) for d in sysm.dq),
        ),
        _scalar(
            "energy",
            "Mechanical energy in the ground frame while rocking about s; ag and agy are ignored.",
            eq.energy,
            sp.Symbol("E", real=True),
        ),
        _scalar(
            "power",
            "Rate of the mechanical energy along solutions: dissipation plus the work of the inertial ground force.",
            eq.power,
            sp.Symbol("Edot", real=True),
        ),
        _scalar(
            "uplift_energy",
            "Least energy above rest at which the attached bodies can lift the block about s in full contact "
            "without ground motion (inf: never; 0: no bound derived); y, ag and agy are ignored.",
            eq.uplift_energy,
            sp.Symbol("E_uplift", real=True),
        ),
        _scalar(
            "least_potential",
            "Least potential energy at the tilt theta about s over every position of the attached bodies, bumpers "
            "left out (-inf: no bound); the other coordinates, the velocities, ag and agy are ignored.",
            eq.least_potential,
            sp.Symbol("V_least", real=True),
        ),
        _scalar(
            "least_stroke_potential",
            "Least potential energy at the tilt theta about s with q[1] held, over the positions of the other "
            "attached bodies, bumpers left out (-inf: no bound); the velocities, ag and agy are ignored.",
            eq.least_stroke_potential,
            sp.Symbol("V_stroke", real=True),
        ),
        _scalar(
            "critical_angle",
            "Static critical angle about the pivot s, the other coordinates held (sign of s).",
            eq.critical_angle,
            theta_cr,
        ),
        Function(
            "stop_gaps",
            "Penetration delta of each side of each end stop (its bumper acts while delta > 0); none without stops.",
            tuple(eq.stop_gaps),
            tuple(f"delta[{i}]" for i in range(len(eq.stop_gaps))),
            tuple(delta[i] for i in range(len(eq.stop_gaps))),
        ),
        Function(
            "stop_forces",
            "Force of each bumper on its travel, max(0, k_b delta + c_b ddelta) while delta > 0, else 0 (> 0: pushes "
            "back; a pad only pushes).",
            tuple(eq.stop_forces),
            tuple(f"F_b[{i}]" for i in range(len(eq.stop_forces))),
            tuple(force[i] for i in range(len(eq.stop_forces))),
        ),
        Function(
            "stop_contact",
            "Contact of each bumper, min(delta, k_b delta + c_b ddelta) (Hunt-Crossley: min(delta, v_in + chi "
            "ddelta)): > 0 exactly while it pushes (the regime of the state); its zeros are the events of the regime.",
            tuple(eq.stop_contact),
            tuple(f"contact[{i}]" for i in range(len(eq.stop_contact))),
            tuple(contact[i] for i in range(len(eq.stop_contact))),
        ),
        Function(
            "stop_approach",
            "Rate of the penetration ddelta of each side of each end stop: where a contact starts (ddelta >= 0), "
            "max(ddelta, approach_floor) is a Hunt-Crossley pad's memory v_in.",
            tuple(eq.stop_approach),
            tuple(f"ddelta[{i}]" for i in range(len(eq.stop_approach))),
            tuple(sp.IndexedBase("ddelta")[i] for i in range(len(eq.stop_approach))),
        ),
        _scalar(
            "critical_tangent",
            "Tangent of the static critical angle about the pivot s where the weights' centre is above the "
            "ground (the angle is then its atan), NaN elsewhere.",
            eq.critical_tangent,
            sp.tan(theta_cr),
        ),
        _affine(
            "block_accelerations",
            "Absolute horizontal accelerations [m/s^2] of the centre of the block's top side (a_top) and of its "
            "centroid (a_cm) while rocking about s, each as out[0] + sum_j out[1 + j] ddq_j.",
            ("a_top", "a_cm"),
            eq.block_accelerations,
            sysm.ddq,
        ),
        _affine(
            "base_reaction",
            "Base shear V_b [N] (the ground's horizontal force on the block and its bodies, > 0 to the right), "
            "vertical reaction N_b [N] (> 0 up) and overturning moment M_b [N m] (minus the reaction's moment "
            "about the centre of the base, > 0 counter-clockwise) while rocking about s, each as "
            "out[0] + sum_j out[1 + j] ddq_j.",
            ("V_b", "N_b", "M_b"),
            eq.base_reaction,
            sysm.ddq,
        ),
        Function(
            "element_forces",
            "Force (moment, for an angle) of the springs, dashpots and bumpers of each attached coordinate on the "
            "block along it, dV_e/dq + dD/ddq (omd: the guide force k_m x + c dx plus the bumpers'); none for the "
            "bare block.",
            tuple(eq.element_forces),
            tuple(f"Q[{q}]" for q in names[1:]),
            tuple(sp.IndexedBase("Q")[q] for q in sysm.q[1:]),
            in_run=False,
        ),
    ]
    if friction:
        table += friction_functions(eq)
    if flies:
        table += flight_functions(eq)
    gravity = sp.Symbol("g", real=True)
    return [
        dataclasses.replace(f, effective_gravity=any(o.has(gravity) for o in f.outputs))
        if eq.vertical and f.name in EFFECTIVE_GRAVITY + FRICTION_GRAVITY + FLIGHT_GRAVITY
        else f
        for f in table
    ]


#: The friction's functions written with ``g`` standing for ``g + agy`` (from the accelerations and reactions).
FRICTION_GRAVITY = ("slide_accel", "contact_slide_accel", "slide_uplift", "stick_force", "contact_stick_force")
#: The flight's functions written so (the flight's accelerations, from the rocking ones).
FLIGHT_GRAVITY = ("flight_accel",)


def friction_functions(eq: Equations) -> list[Function]:
    """The functions of the phases of a floor with friction (docs/model.md section 15, :mod:`.friction`).

    Each takes the arguments of every function, then its own (:attr:`Function.inputs`): ``mu_slip``, the
    kinetic coefficient signed by the slip's direction (``mu_k sign(du)``), and for the slip's energy and
    the impacts ``du``, the slip speed (before the impact).
    """
    sysm = eq.system
    names = [str(q) for q in sysm.q]
    acc = tuple("dd" + q for q in names) + ("ddu",)
    ddu, N, F = (sp.Symbol(n, real=True) for n in ("ddu", "N", "F"))
    P_t, P_n = sp.Symbol("P_t", real=True), sp.Symbol("P_n", real=True)
    du_plus = sp.Symbol("du_plus", real=True)
    mu = Argument(str(friction.mu_slip), "mu_k sign(du): the kinetic friction coefficient signed by the slip")
    du = Argument(str(friction.du_before), "slip speed of the base relative to the ground [m/s]")
    sliding, fimpact, held = friction.sliding(eq), friction.friction_impact(eq), friction.contact(eq)
    after = tuple("d" + q + "_plus" for q in names) + ("du_plus", "P_t", "P_n")
    after_symbols = tuple(_after_impact(d) for d in sysm.dq) + (du_plus, P_t, P_n)

    def made(name, doc, outputs, labels, symbols, inputs):
        return Function(name, doc, tuple(outputs), labels, symbols, in_run=False, inputs=inputs, hoisted=False)

    return [
        made(
            "slide_accel",
            "Accelerations while rocking about s with the pivot sliding (slide-rock), then the slip's ddu and the "
            "floor's normal force N [N]; the friction force is -mu_slip N.",
            [*sliding.slide_accel, sliding.slide_normal],
            acc + ("N",),
            tuple(sysm.ddq) + (ddu, N),
            (mu,),
        ),
        made(
            "contact_slide_accel",
            "Accelerations in full contact with the base sliding (ddtheta = 0), then ddu and the floor's normal "
            "force N [N].",
            [*sliding.contact_slide_accel, sliding.contact_slide_normal],
            acc + ("N",),
            tuple(sysm.ddq) + (ddu, N),
            (mu,),
        ),
        made(
            "slide_uplift",
            "Uplift function about the pivot s in full contact while the base slides.",
            [sliding.slide_uplift],
            ("",),
            (sp.Symbol("u_s", real=True),),
            (mu,),
        ),
        made(
            "stick_force",
            "Tangential force F = V_b and normal force N = N_b [N] the floor holds while rocking about s with "
            "the pivot stuck (|F| <= mu_s N keeps it).",
            held.stick_force,
            ("F", "N"),
            (F, N),
            (),
        ),
        made(
            "contact_stick_force",
            "Tangential force F and normal force N [N] the floor holds in full contact with the base stuck.",
            held.contact_stick_force,
            ("F", "N"),
            (F, N),
            (),
        ),
        made(
            "slip_energy",
            "Kinetic energy [J] the slip speed du adds to the energy in the ground frame.",
            [held.slip_energy],
            ("",),
            (sp.Symbol("E_u", real=True),),
            (du,),
        ),
        made(
            "impact_stick",
            "Velocities after an impact at theta = 0 that ends rocking about s when the new corner sticks (du "
            "after is 0), then the floor's impulses P_t, P_n [N s] on it; ag and agy are ignored.",
            fimpact.stick,
            after,
            after_symbols,
            (du,),
        ),
        made(
            "impact_slide",
            "Velocities after an impact at theta = 0 that ends rocking about s when the new corner slides, "
            "P_t = -mu_slip P_n, then the impulses P_t, P_n [N s]; ag and agy are ignored.",
            fimpact.slide,
            after,
            after_symbols,
            (du, mu),
        ),
    ]


def flight_functions(eq: Equations) -> list[Function]:
    """The functions of flight and landing (docs/model.md section 16, :mod:`.flight`), not hoisted.

    The state of a flying block is its rocking state about a reference corner ``s`` and that corner's
    displacement ``(u, v)`` relative to its place at rest on the ground, with the rates ``du``, ``dv``: the
    functions take those they need as their own inputs. The restitution ``e_n`` and ``mu_slip`` of a landing too.
    """
    sysm = eq.system
    names = [str(q) for q in sysm.q]
    acc = tuple("dd" + q for q in names) + ("ddu", "ddv")
    corner = {
        "u": "horizontal displacement of the corner s from its place at rest on the ground [m]",
        "v": "height of the corner s above the floor [m]",
        "du": "horizontal velocity of the corner s relative to the ground [m/s]",
        "dv": "vertical velocity of the corner s relative to the ground [m/s]",
    }
    u, v, du, dv = (Argument(name, doc) for name, doc in corner.items())
    e_n = Argument(str(flight.e_n), "normal coefficient of restitution of the landing, in [0, 1]; 0: plastic")
    mu = Argument(str(friction.mu_slip), "mu_k times the sign of the corner's slip: P_t = -mu_slip P_n")
    landing = flight.landing(eq)
    after = tuple("d" + q + "_plus" for q in names) + ("du_plus", "dv_plus", "P_t", "P_n")
    after_symbols = tuple(_after_impact(d) for d in sysm.dq) + tuple(
        sp.Symbol(n, real=True) for n in ("du_plus", "dv_plus", "P_t", "P_n")
    )
    other = ("u_o", "v_o", "du_o", "dv_o")
    flat = flight.flat_landing(eq)
    flat_after = after[:-1] + ("P_s", "P_o")
    flat_symbols = after_symbols[:-1] + tuple(sp.Symbol(n, real=True) for n in ("P_s", "P_o"))

    def made(name, doc, outputs, labels, symbols, inputs):
        return Function(name, doc, tuple(outputs), labels, symbols, in_run=False, inputs=inputs, hoisted=False)

    return [
        made(
            "flight_accel",
            "Accelerations in flight, the block free of the floor: ddq, then ddu and ddv of the corner s (its "
            "horizontal and vertical acceleration relative to the ground).",
            flight.flight_accel(eq),
            acc,
            tuple(sysm.ddq) + tuple(sp.Symbol(n, real=True) for n in ("ddu", "ddv")),
            (),
        ),
        made(
            "corner_heights",
            "Heights [m] above the floor of the corner s (v itself) and of the corner -s: a landing where one "
            "reaches 0 moving down.",
            flight.corner_heights(eq),
            ("y_s", "y_other"),
            tuple(sp.Symbol(n, real=True) for n in ("y_s", "y_other")),
            (v,),
        ),
        made(
            "flight_corner",
            "The corner -s's u, v, du, dv from those of the corner s: the flying state about the other corner "
            "(u from its own place at rest).",
            flight.other_corner(eq),
            other,
            tuple(sp.Symbol(n, real=True) for n in other),
            (u, v, du, dv),
        ),
        made(
            "flight_energy",
            "Mechanical energy [J] in the ground frame while flying: energy with the corner's velocity and height.",
            [flight.flight_energy(eq)],
            ("",),
            (sp.Symbol("E", real=True),),
            (v, du, dv),
        ),
        made(
            "landing_stick",
            "Velocities after the corner s lands and sticks (du after is 0, dv after is -e_n dv), then the floor's "
            "impulses P_t, P_n [N s] on it; valid while |P_t| <= mu_s P_n; ag and agy are ignored.",
            landing.stick,
            after,
            after_symbols,
            (du, dv, e_n),
        ),
        made(
            "landing_slide",
            "Velocities after the corner s lands and slides, P_t = -mu_slip P_n (dv after is -e_n dv), then the "
            "impulses P_t, P_n [N s]; ag and agy are ignored.",
            landing.slide,
            after,
            after_symbols,
            (du, dv, e_n, mu),
        ),
        made(
            "flat_landing_stick",
            "Velocities after the base lands flat on both corners at theta = 0 and sticks (dtheta and du after are 0, "
            "dv after is -e_n dv), then the floor's impulses P_t and P_s, P_o [N s] on the corners s and -s; valid "
            "while P_s, P_o >= 0 and |P_t| <= mu_s (P_s + P_o); theta, ag and agy are ignored.",
            flat.stick,
            flat_after,
            flat_symbols,
            (du, dv, e_n),
        ),
        made(
            "flat_landing_slide",
            "Velocities after the base lands flat on both corners at theta = 0 and slides, P_t = -mu_slip (P_s + "
            "P_o), then the impulses P_t, P_s, P_o [N s]; theta, ag and agy are ignored.",
            flat.slide,
            flat_after,
            flat_symbols,
            (du, dv, e_n, mu),
        ),
    ]


def _affine(name: str, doc: str, quantities: tuple, outputs, accelerations) -> Function:
    """A function of quantities affine in the accelerations, as ``affine_in_accelerations`` lists them."""
    keys = (sp.Integer(0),) + tuple(accelerations)
    return Function(
        name,
        doc,
        tuple(outputs),
        tuple(f"{q}[{k}]" for q in quantities for k in keys),
        tuple(sp.IndexedBase(q)[k] for q in quantities for k in keys),
        in_run=False,
    )


def _after_impact(velocity: sp.Symbol) -> sp.Symbol:
    """The symbol of ``velocity`` just after an impact."""
    return sp.Symbol(velocity.name + "_plus", real=True)


@dataclass(frozen=True)
class Argument:
    """One argument of every generated function."""

    name: str
    doc: str


def arguments(eq: Equations, spec) -> list[Argument]:
    """Arguments of every generated function, in order, with their meaning."""
    sysm = eq.system
    args = [Argument("s", "pivot: +1 rocking about A (left corner), -1 about A' (right corner)")]
    coord_doc = {str(sysm.q[0]): "rocking angle [rad]"}
    coord_doc.update({c: f"coordinate {c} of the attached bodies" for c in spec.coordinates})
    args += [Argument(str(q), coord_doc[str(q)]) for q in sysm.q]
    args += [Argument(str(d), f"time derivative of {q}") for q, d in zip(sysm.q, sysm.dq)]
    args.append(Argument("ag", "ground acceleration ddx_g [m/s^2], positive to the right"))
    if eq.vertical:
        args.append(Argument("agy", "vertical ground acceleration ddy_g [m/s^2], positive up"))
    else:
        args.append(Argument("agy", "vertical ground acceleration ddy_g [m/s^2]: ignored, the model takes none"))
    pdoc = {p.name: f"{p.doc} [{p.unit}]" for p in spec.all_parameters}
    args += [Argument(str(p), pdoc[str(p)]) for p in sysm.params]
    return args


@dataclass(frozen=True)
class Cse:
    """Expressions after common-subexpression elimination.

    Attributes
    ----------
    subs : tuple of (Symbol, Expr)
        The temporaries ``cse<i>``, each in terms of the ones before it.
    outputs : tuple of Expr
        The expressions in terms of the temporaries.
    """

    subs: tuple
    outputs: tuple

    def uses(self, names) -> list[str]:
        """Those of ``names`` that the expressions read, in the order of ``names``."""
        exprs = [b for _, b in self.subs] + list(self.outputs)
        free = {str(a) for e in exprs for a in sp.sympify(e).free_symbols}
        return [n for n in names if n in free]


def common_subexpressions(outputs, start: int = 0) -> Cse:
    """:class:`Cse` of ``outputs``, its temporaries named so that no model symbol can clash with them
    (``cse<start>`` first)."""
    subs, outs = sp.cse(list(outputs), symbols=sp.numbered_symbols("cse", start=start), order="canonical")
    return Cse(tuple(subs), tuple(outs))


def hoist_constants(outputs, varying):
    """Split expressions into constants of the parameters and what varies along a run.

    Every largest subexpression that depends on none of ``varying`` (the state
    and the ground accelerations) becomes a symbol ``cst<i>``, the same symbol wherever it
    recurs; the terms of a sum that differ only by such a factor are gathered
    first, so that ``a x + b x`` costs one constant ``a + b``. A runtime
    computes the constants once per run, pivot and regime of the stops, not at every call, all of
    them: one that only a branch of a ``Piecewise`` uses is computed even where
    that branch is not taken (an inf or NaN there is never read).

    Returns
    -------
    constants : list of (Symbol, Expr)
        In order of first use.
    outputs : list of Expr
        The outputs in terms of ``varying`` and the constants.
    """
    varying = set(varying)
    table: dict = {}

    def constant(expr):
        if expr.is_number:
            return expr
        if expr not in table:
            table[expr] = sp.Symbol(f"cst{len(table)}", real=True)
        return table[expr]

    def walk(expr):
        if not isinstance(expr, sp.Expr):  # a condition of a Piecewise, its (expression, condition) pairs
            return expr.func(*(walk(a) for a in expr.args)) if expr.args else expr
        if not (expr.free_symbols & varying):
            return constant(expr)
        if not expr.args:
            return expr
        if expr.is_Add:
            gathered: dict = {}
            for term in expr.args:
                coefficient, rest = term.as_independent(*varying, as_Add=False)
                gathered.setdefault(rest, []).append(coefficient)
            return sp.Add(*(constant(sp.Add(*c)) * walk(rest) for rest, c in gathered.items()))
        if expr.is_Mul:
            coefficient, rest = expr.as_independent(*varying, as_Add=False)
            return constant(coefficient) * sp.Mul(*(walk(f) for f in sp.Mul.make_args(rest)))
        return expr.func(*(walk(a) for a in expr.args))

    hoisted = [walk(sp.sympify(o)) for o in outputs]
    return [(symbol, expr) for expr, symbol in table.items()], hoisted


@dataclass(frozen=True)
class Prepared:
    """The functions split for a run (:func:`hoist_constants`): what the C back end computes.

    Attributes
    ----------
    constants : tuple of str
        Names of the constants ``cst<i>``, in order.
    prepare : Cse
        The constants, from the pivot, the regime of the stops and the parameters.
    functions : tuple of Cse
        Each function of the table, from the state, ``ag`` (``agy`` for the power) and the constants.
    """

    constants: tuple
    prepare: Cse
    functions: tuple


def prepare_run(functions: list[Function], state: tuple) -> Prepared:
    """Hoist the constants of a run out of every function of the table at once (shared across functions).

    The constants first used by the functions that are not ``in_run`` come last (constants are
    numbered in order of first use, and those functions last in the table) and get their own
    common subexpressions, after the others: what a run prepares is computed as before. The
    terms in ``agy`` (the power's) are hoisted after all the rest, and their constants come
    last with common subexpressions of their own, for the same reason.
    """
    if any(f.in_run and not e.in_run for e, f in zip(functions, functions[1:])):
        raise ValueError("the functions a simulator calls while it integrates come first in the table")
    varying = [sp.Symbol(n, real=True) for n in state] + [ag, agy]
    outputs = [sp.sympify(o) for f in functions for o in f.outputs]
    still = [o.xreplace({agy: 0}) for o in outputs]
    known = len(hoist_constants(still, varying)[0])
    moving = [sp.expand(o - w) if o.has(agy) else sp.Integer(0) for o, w in zip(outputs, still)]
    constants, hoisted = hoist_constants(still + moving, varying)
    hoisted = [w + v for w, v in zip(hoisted[: len(outputs)], hoisted[len(outputs) :])]
    in_run = hoisted[: sum(len(f.outputs) for f in functions if f.in_run)]
    used = set().union(*(o.free_symbols for o in in_run)) if in_run else set()
    first = sum(1 for symbol, _ in constants[:known] if symbol in used)
    groups, start = [], 0
    for block in (constants[:first], constants[first:known], constants[known:]):
        groups.append(common_subexpressions([expr for _, expr in block], start=start))
        start += len(groups[-1].subs)
    prepare = Cse(sum((c.subs for c in groups), ()), sum((c.outputs for c in groups), ()))
    split, start = [], 0
    for f in functions:
        split.append(common_subexpressions(hoisted[start : start + len(f.outputs)]))
        start += len(f.outputs)
    return Prepared(tuple(str(symbol) for symbol, _ in constants), prepare, tuple(split))


def input_hash(spec, options: dict) -> str:
    """SHA-256 of what the generated files depend on: spec, options, derive's code."""
    h = hashlib.sha256()
    h.update(spec.source.encode())
    h.update(json.dumps(options, sort_keys=True).encode())
    here = Path(__file__).parent
    for path in sorted(list(here.glob("*.py")) + list(TEMPLATES.glob("*.j2"))):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


@dataclass(frozen=True)
class ModelContext:
    """Everything the back ends render a model from, built once by :func:`model_context`.

    Attributes
    ----------
    name, title : str
        The spec's name (file names, C prefix) and one-line description.
    options : dict
        Resolved derivation options.
    coordinates, state, params : tuple of str
        Coordinates (``theta`` first), state ``(q, dq)`` and parameters, in argument order.
    units : dict
        The unit of each state component by name (``rad``, ``m``, ``rad/s``, ``m/s``).
    kinematics : tuple of (Symbol, Symbol, Symbol)
        Each coordinate with its velocity and acceleration symbols.
    arguments : tuple of Argument
        The arguments of every function, in order.
    parameters : tuple of Parameter
        Unit, meaning and valid range of each parameter, in argument order.
    block_parameters : tuple of str
        The parameters the block sets, in argument order.
    functions : tuple of Function
        The table of generated functions.
    cse : tuple of Cse
        Each function's outputs after common-subexpression elimination.
    prepared : Prepared
        The functions split into the constants of a run and the rest.
    regime : tuple of str
        The indicator of each stop side (``System.stops``), in the order of ``stop_gaps``,
        then the memory ``v_in`` of each Hunt-Crossley side (none without one).
    state_regime : tuple of Expr
        The regime of a state, each indicator from its contact (the bumper pushes), each
        memory as if a contact started there: what a function takes when it is given none.
    stops : tuple of dict
        Per stop side, its ``law`` and ``approach_floor`` (0 for Kelvin-Voigt).
    vertical : bool
        Whether the model takes vertical ground motion (``Equations.vertical``).
    inputs_sha256 : str
        :func:`input_hash` of the spec and options.
    """

    name: str
    title: str
    options: dict
    coordinates: tuple
    state: tuple
    units: dict
    params: tuple
    kinematics: tuple
    arguments: tuple
    parameters: tuple
    block_parameters: tuple
    functions: tuple
    cse: tuple
    prepared: Prepared
    regime: tuple
    state_regime: tuple
    stops: tuple
    vertical: bool
    inputs_sha256: str


def model_context(eq: Equations, spec) -> ModelContext:
    """Build the context of a derived model: the table, the arguments, the expressions ready to print."""
    sysm = eq.system
    coordinates = tuple(str(q) for q in sysm.q)
    state = coordinates + tuple(str(d) for d in sysm.dq)
    params = tuple(str(p) for p in sysm.params)
    functions = tuple(model_functions(eq, spec.friction, spec.flight))
    block = {p[0] for p in BLOCK_PARAMETERS}
    units = coordinate_units(spec)
    units.update({"d" + q: unit + "/s" for q, unit in units.items()})
    return ModelContext(
        name=spec.name,
        title=spec.title,
        options=eq.options,
        coordinates=coordinates,
        state=state,
        units={name: units[name] for name in state},
        params=params,
        kinematics=tuple(zip(sysm.q, sysm.dq, sysm.ddq)),
        arguments=tuple(arguments(eq, spec)),
        parameters=tuple(p for p in spec.all_parameters if p.name in params),
        block_parameters=tuple(p for p in params if p in block),
        functions=functions,
        cse=tuple(common_subexpressions(f.outputs) for f in functions),
        prepared=prepare_run([f for f in functions if f.hoisted], state),
        regime=tuple(str(on) for on, *_ in sysm.stops) + tuple(str(v) for v in eq.stop_memory),
        state_regime=tuple(eq.stop_regime),
        stops=tuple(
            {"law": pad.law, "approach_floor": pad.approach_floor if pad.hunt_crossley else 0.0}
            for *_, pad in sysm.stops
        ),
        vertical=eq.vertical,
        inputs_sha256=input_hash(spec, eq.options),
    )


@functools.cache
def _environment() -> jinja2.Environment:
    """The templates, loaded once per process, with one escaping filter per target language.

    The spec's free text was checked already (:func:`rocking.derive.names.check_text`); the
    templates escape it once more where it lands (``pydoc``, ``ccomment``, ``md``), so that no
    text can close a docstring or a comment even if a check is ever loosened.
    """
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(TEMPLATES),
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        undefined=jinja2.StrictUndefined,
    )
    env.filters.update(pydoc=escape_python_doc, ccomment=escape_c_comment, md=escape_markdown)
    return env


class Generator:
    """One back end: renders files of a model from its context alone."""

    #: The stage of the derivation it is (:func:`generate`).
    stage = "files"

    def __init__(self, model: ModelContext):
        self.model = model

    def render(self, template: str, **fields) -> str:
        """Render ``template`` with the fields every template shares and ``fields``."""
        m = self.model
        shared = {
            "name": m.name,
            "title": m.title,
            "coordinates": list(m.coordinates),
            "state": list(m.state),
            "params": list(m.params),
            "args": list(m.arguments),
            "options": m.options,
            "nq": len(m.coordinates),
        }
        return _environment().get_template(template).render(**shared, **fields)

    def files(self) -> dict[str, str]:
        """Map of file name to text."""
        raise NotImplementedError


def _printed(f: Function, cse: Cse, printer) -> dict:
    """The fields of one function in a template, its expressions printed by ``printer``."""
    return {
        "name": f.name,
        "doc": f.doc,
        "labels": f.labels,
        "scalar": f.scalar,
        "subs": [(str(a), printer.doprint(b)) for a, b in cse.subs],
        "outs": [printer.doprint(o) for o in cse.outputs],
    }


def _state_regime(model: ModelContext, printer) -> dict:
    """The regime of a state (:attr:`ModelContext.state_regime`) printed by ``printer``, with what it reads."""
    cse = common_subexpressions(model.state_regime)
    return {
        "subs": [(str(a), printer.doprint(b)) for a, b in cse.subs],
        "outs": [printer.doprint(o) for o in cse.outputs],
        "state": _read(model.state, cse),
        "params": _read(model.params, cse),
    }


class NumpyGenerator(Generator):
    """A NumPy module whose functions broadcast over states and parameters."""

    stage = "NumPy code"

    def files(self):
        m = self.model
        printer = NumPyPrinter({"fully_qualified_modules": True})
        funcs = [
            dict(
                _printed(f, c, printer),
                regime=bool(c.uses(m.regime)),
                effective_gravity=f.effective_gravity,
                inputs=list(f.inputs),
            )
            for f, c in zip(m.functions, m.cse)
        ]
        regime = _state_regime(m, printer)
        imports = sorted(set(printer.module_imports) | {"numpy"})
        fields = {"functions": funcs, "imports": imports, "regime": list(m.regime), "state_regime": regime}
        fields["n_stops"] = len(m.stops)
        return {"model.py": self.render("numpy_model.py.j2", **fields)}


class _C99(C99CodePrinter):
    """C99 printer that writes small integer powers as products (exact, no libm call)."""

    def _print_Pow(self, expr):
        if expr.exp.is_Integer and 2 <= expr.exp <= 4:
            base = self.parenthesize(expr.base, 100)
            return "(" + "*".join([base] * int(expr.exp)) + ")"
        return super()._print_Pow(expr)

    def _print_Piecewise(self, expr):
        """Nested conditional expressions on one line (SymPy's own spread one over several)."""
        if expr.args[-1].cond != True:  # noqa: E712 - SymPy's true, not Python's
            raise ValueError("a Piecewise without a default branch cannot be printed as an expression")
        text = self._print(expr.args[-1].expr)
        for branch in reversed(expr.args[:-1]):
            text = f"(({self._print(branch.cond)}) ? ({self._print(branch.expr)}) : ({text}))"
        return text


def _read(names, cse: Cse) -> list[tuple[int, str]]:
    """``(index, name)`` of those of ``names`` that ``cse`` reads: the array elements a C function loads."""
    used = set(cse.uses(names))
    return [(i, n) for i, n in enumerate(names) if n in used]


class CGenerator(Generator):
    """C99 source and header: pure functions of doubles, no allocation, no globals.

    The constants of a run (:func:`hoist_constants`: every subexpression of
    the parameters, the pivot and the regime of the stops alone) come from
    ``prefix_prepare(s, on, p, cst)``;
    ``prefix_<name>_prepared(y, ag, cst[, out])`` is the work left per call,
    what a runtime calls in its inner loop (``prefix_power_prepared`` also takes
    ``agy``, which enters it otherwise than with gravity). ``prefix_<name>(s, y,
    ag, agy, p[, out])`` prepares, at the effective gravity ``g + agy`` for the
    functions that read it so, and calls it: the interface of every back end.
    """

    stage = "C code"

    def files(self):
        m = self.model
        printer = _C99()
        run = m.prepared
        prepare = {
            "uses_s": bool(run.prepare.uses(["s"])),
            "regime": _read(m.regime, run.prepare),
            "params": _read(m.params, run.prepare),
            "subs": [(str(a), printer.doprint(b)) for a, b in run.prepare.subs],
            "outs": [printer.doprint(o) for o in run.prepare.outputs],
        }
        hoisted = [f for f in m.functions if f.hoisted]
        funcs = [
            dict(
                _printed(f, c, printer),
                uses_ag=bool(c.uses(["ag"])),
                reads_agy=bool(c.uses(["agy"])),
                effective_gravity=f.effective_gravity,
                state=_read(m.state, c),
                constants=_read(run.constants, c),
            )
            for f, c in zip(hoisted, run.functions)
        ]
        direct = [
            dict(
                _printed(f, c, printer),
                uses_s=bool(c.uses(["s"])),
                uses_ag=bool(c.uses(["ag"])),
                reads_agy=bool(c.uses(["agy"])) or f.effective_gravity,
                effective_gravity=f.effective_gravity,
                state=_read(m.state, c),
                params=[(i, n) for i, n in _read(m.params, c) if not (f.effective_gravity and n == "g")],
                regime=_read(m.regime, c),
                inputs=[a.name for a in f.inputs],
            )
            for f, c in zip(m.functions, m.cse)
            if not f.hoisted
        ]
        fields = {
            "prepare": prepare,
            "functions": funcs,
            "direct": direct,
            "state_regime": _state_regime(m, printer),
            "n_constants": len(run.constants),
            "n_stops": len(m.stops),
            "n_regime": len(m.regime),
            "flight": any(f.name == "flight_accel" for f in m.functions),
            "stop_floors": ", ".join(repr(side["approach_floor"]) for side in m.stops),
            "prefix": m.name,
            "PREFIX": m.name.upper(),
        }
        return {
            f"{m.name}.h": self.render("model.h.j2", **fields),
            f"{m.name}.c": self.render("model.c.j2", **fields),
        }


#: How EQUATIONS.md shows the outputs of some functions, to be read against the paper;
#: the others are shown as derived.
_SHOWN = {
    "mass_matrix": lambda e: sp.collect(e, s),
    "impact": lambda e: sp.factor_terms(sp.cancel(e)),
}


class LatexGenerator(Generator):
    """EQUATIONS.md: every function of the table in LaTeX, to hold against the paper."""

    stage = "LaTeX"

    def files(self):
        names = {ag: r"\ddot{x}_g", agy: r"\ddot{y}_g"}
        for q, dq, ddq in self.model.kinematics:
            names[dq] = r"\dot{" + sp.latex(q) + "}"
            names[ddq] = r"\ddot{" + sp.latex(q) + "}"
            names[_after_impact(dq)] = r"\dot{" + sp.latex(q) + "}^{+}"
        for name in ("u", "v"):  # the flying corner's rates (docs/model.md section 16)
            names[sp.Symbol("d" + name, real=True)] = rf"\dot{{{name}}}"
            names[sp.Symbol("dd" + name, real=True)] = rf"\ddot{{{name}}}"
            names[sp.Symbol(f"d{name}_plus", real=True)] = rf"\dot{{{name}}}^{{+}}"
        names.update({sp.Symbol(on, real=True): rf"\mathrm{{on}}_{{{i}}}" for i, on in enumerate(self.model.regime)})
        names.update(
            {
                sp.Symbol(v, positive=True): rf"v_{{\mathrm{{in}},{v[4:]}}}"
                for v in self.model.regime
                if v.startswith("_vin")
            }
        )

        def tex(expr):
            return sp.latex(expr, symbol_names=names)

        gravity = sp.Symbol("g", real=True)
        sections = []
        for f in self.model.functions:
            shown = _SHOWN.get(f.name, lambda e: e)
            outputs = [o.xreplace({gravity: gravity + agy}) if f.effective_gravity else o for o in f.outputs]
            equations = [(tex(y), tex(shown(o))) for y, o in zip(f.symbols, outputs)]
            sections.append({"name": f.name, "doc": f.doc, "equations": equations})
        coordinates = [sp.latex(q) for q, _, _ in self.model.kinematics]
        regime = [
            (tex(sp.Symbol(on, positive=True) if on.startswith("_vin") else sp.Symbol(on, real=True)), tex(expr))
            for on, expr in zip(self.model.regime, self.model.state_regime)
        ]
        fields = {"functions": sections, "coordinates_tex": coordinates, "regime": regime}
        return {"EQUATIONS.md": self.render("EQUATIONS.md.j2", **fields)}


class ManifestGenerator(Generator):
    """manifest.json: what the model is, so a runtime can use it without knowing it."""

    def __init__(self, model: ModelContext, produced: dict[str, str]):
        super().__init__(model)
        self.produced = produced

    def files(self):
        m = self.model
        data = {
            "format": MANIFEST_FORMAT,
            "model": m.name,
            "title": m.title,
            "options": m.options,
            "coordinates": list(m.coordinates),
            "state": list(m.state),
            "units": dict(m.units),
            "parameters": [_parameter_entry(p) for p in m.parameters],
            "block_parameters": list(m.block_parameters),
            "arguments": [a.name for a in m.arguments],
            "functions": {
                f.name: {
                    "outputs": len(f.outputs),
                    "scalar": f.scalar,
                    "doc": f.doc,
                    "inputs": [a.name for a in f.inputs],
                }
                for f in m.functions
            },
            "friction": any(f.name == "slide_accel" for f in m.functions),
            "flight": any(f.name == "flight_accel" for f in m.functions),
            "regime": list(m.regime),
            "vertical": m.vertical,
            "stops": [dict(side) for side in m.stops],
            "files": {
                "numpy": "model.py",
                "c_source": f"{m.name}.c",
                "c_header": f"{m.name}.h",
                "c_prefix": m.name,
                "equations": "EQUATIONS.md",
            },
            "sha256": {name: hashlib.sha256(text.encode()).hexdigest() for name, text in sorted(self.produced.items())},
            "sympy": sp.__version__,
            "inputs_sha256": m.inputs_sha256,
        }
        return {"manifest.json": json.dumps(data, indent=2, sort_keys=True) + "\n"}


def _parameter_entry(p: Parameter) -> dict:
    """A parameter as manifest.json lists it."""
    return {"name": p.name, "unit": p.unit, "doc": p.doc, "valid": p.valid}


BACKENDS = (NumpyGenerator, CGenerator, LatexGenerator)


def generate(eq: Equations, spec, stage=lambda name: None) -> dict[str, str]:
    """All files of a model, keyed by file name: one context, handed to every back end.

    ``stage`` is called with the name of each stage as it begins, as by
    :func:`rocking.derive.equations.derive`.
    """
    stage("common subexpressions")
    model = model_context(eq, spec)
    out: dict[str, str] = {}
    for backend in BACKENDS:
        stage(backend.stage)
        out.update(backend(model).files())
    out.update(ManifestGenerator(model, dict(out)).files())
    return out
