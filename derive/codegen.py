"""From derived expressions to files: one generator interface, one class per back end.

Every model exposes the same functions with the same arguments, so that a
runtime can drive any model from its manifest alone:

``name(s, <q...>, <dq...>, ag, <params...>)`` in NumPy, and
``prefix_name(double s, const double *y, double ag, const double *p[, double *out])``
in C, with ``y = (q, dq)`` and ``p`` in manifest order. Arguments a function
does not need are accepted and ignored.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import jinja2
import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.numpy import NumPyPrinter

from .equations import Equations
from .mechanics import ag, s

TEMPLATES = Path(__file__).parent / "templates"
FORMAT_VERSION = 1


@dataclass(frozen=True)
class Function:
    """One generated function: its outputs, in order, and what they mean."""

    name: str
    doc: str
    outputs: tuple
    labels: tuple

    @property
    def scalar(self) -> bool:
        return len(self.outputs) == 1 and self.labels == ("",)


def model_functions(eq: Equations) -> list[Function]:
    """The generated interface of a derived model, in a fixed order."""
    sysm = eq.system
    names = [str(q) for q in sysm.q]
    n = len(names)
    acc = tuple("dd" + q for q in names)
    return [
        Function(
            "mass_matrix",
            "Mass matrix of the rocking phase about the pivot s, row-major.",
            tuple(eq.mass_matrix[i, j] for i in range(n) for j in range(n)),
            tuple(f"M[{i},{j}]" for i in range(n) for j in range(n)),
        ),
        Function(
            "forcing",
            "Forcing of the rocking phase about the pivot s: mass_matrix @ ddq = forcing.",
            tuple(eq.forcing),
            tuple(f"f[{q}]" for q in names),
        ),
        Function(
            "rocking_accel",
            "Accelerations while rocking about the pivot s (finite ddtheta as the attached masses vanish).",
            tuple(eq.rocking_accel),
            acc,
        ),
        Function(
            "contact_accel",
            "Accelerations in full contact (theta = dtheta = 0); ddtheta is 0 and s is ignored.",
            tuple(eq.contact_accel),
            acc,
        ),
        Function(
            "uplift",
            "Uplift function about the pivot s in full contact: the block leaves the ground when it turns positive.",
            (eq.uplift,),
            ("",),
        ),
        Function(
            "impact",
            "Velocities after an impact at theta = 0 that ends rocking about s (new pivot -s); ag is ignored.",
            tuple(eq.impact),
            tuple("d" + q + "_plus" for q in names),
        ),
        Function(
            "energy",
            "Mechanical energy in the ground frame while rocking about s; ag is ignored.",
            (eq.energy,),
            ("",),
        ),
        Function(
            "power",
            "Rate of the mechanical energy along solutions: dissipation plus the work of the inertial ground force.",
            (eq.power,),
            ("",),
        ),
        Function(
            "uplift_energy",
            "Least energy above rest at which the attached bodies can lift the block about s in full contact "
            "without ground motion (inf: never; 0: no bound derived); y and ag are ignored.",
            (eq.uplift_energy,),
            ("",),
        ),
        Function(
            "critical_angle",
            "Static critical angle about the pivot s, the other coordinates held (sign of s).",
            (eq.critical_angle,),
            ("",),
        ),
        Function(
            "critical_tangent",
            "Tangent of the static critical angle about the pivot s where the weights' centre is above the "
            "ground (the angle is then its atan), NaN elsewhere.",
            (eq.critical_tangent,),
            ("",),
        ),
    ]


@dataclass(frozen=True)
class Argument:
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
    pdoc = {p.name: f"{p.doc} [{p.unit}]" for p in spec.all_parameters}
    args += [Argument(str(p), pdoc[str(p)]) for p in sysm.params]
    return args


def _cse(outputs):
    """Common subexpressions, named so that no model symbol can clash with them."""
    return sp.cse(list(outputs), symbols=sp.numbered_symbols("cse"), order="canonical")


def hoist_constants(outputs, varying):
    """Split expressions into constants of the parameters and what varies along a run.

    Every largest subexpression that depends on none of ``varying`` (the state
    and ``ag``) becomes a symbol ``cst<i>``, the same symbol wherever it
    recurs; the terms of a sum that differ only by such a factor are gathered
    first, so that ``a x + b x`` costs one constant ``a + b``. A runtime
    computes the constants once per run and pivot, not at every call, all of
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


def _used(exprs, names):
    free = set().union(*(sp.sympify(e).free_symbols for e in exprs)) if exprs else set()
    return [n for n in names if sp.Symbol(n, real=True) in free]


class Generator:
    """Base class: renders one or more files of a model from its templates."""

    template_names: tuple = ()

    def __init__(self, eq: Equations, spec):
        self.eq = eq
        self.spec = spec
        self.functions = model_functions(eq)
        self.args = arguments(eq, spec)
        env = jinja2.Environment(
            loader=jinja2.FileSystemLoader(TEMPLATES),
            keep_trailing_newline=True,
            trim_blocks=True,
            lstrip_blocks=True,
            undefined=jinja2.StrictUndefined,
        )
        self.env = env

    def context(self) -> dict:
        sysm = self.eq.system
        return {
            "name": self.spec.name,
            "title": self.spec.title,
            "coordinates": [str(q) for q in sysm.q],
            "state": [str(q) for q in sysm.q] + [str(d) for d in sysm.dq],
            "params": [str(p) for p in sysm.params],
            "args": self.args,
            "options": self.eq.options,
            "nq": len(sysm.q),
        }

    def files(self) -> dict[str, str]:
        """Map of file name to text."""
        raise NotImplementedError


class NumpyGenerator(Generator):
    """A NumPy module whose functions broadcast over states and parameters."""

    def files(self):
        printer = NumPyPrinter({"fully_qualified_modules": True})
        funcs = []
        for f in self.functions:
            subs, outs = _cse(f.outputs)
            funcs.append(
                {
                    "name": f.name,
                    "doc": f.doc,
                    "labels": f.labels,
                    "scalar": f.scalar,
                    "subs": [(str(a), printer.doprint(b)) for a, b in subs],
                    "outs": [printer.doprint(o) for o in outs],
                }
            )
        imports = sorted(set(printer.module_imports) | {"numpy"})
        text = self.env.get_template("numpy_model.py.j2").render(**self.context(), functions=funcs, imports=imports)
        return {"model.py": text}


class _C99(C99CodePrinter):
    """C99 printer that writes small integer powers as products (exact, no libm call)."""

    def _print_Pow(self, expr):
        if expr.exp.is_Integer and 2 <= expr.exp <= 4:
            base = self.parenthesize(expr.base, 100)
            return "(" + "*".join([base] * int(expr.exp)) + ")"
        return super()._print_Pow(expr)


class CGenerator(Generator):
    """C99 source and header: pure functions of doubles, no allocation, no globals.

    The constants of a run (:func:`hoist_constants`: every subexpression of
    the parameters and the pivot alone) come from ``prefix_prepare(s, p, cst)``;
    ``prefix_<name>_prepared(y, ag, cst[, out])`` is the work left per call,
    what a runtime calls in its inner loop. ``prefix_<name>(s, y, ag, p[, out])``
    prepares and calls it: the interface of every back end.
    """

    def files(self):
        printer = _C99()
        ctx = self.context()
        state, params = ctx["state"], ctx["params"]
        varying = [sp.Symbol(n, real=True) for n in state] + [ag]
        outputs = [o for f in self.functions for o in f.outputs]
        constants, hoisted = hoist_constants(outputs, varying)
        subs, outs = _cse([expr for _, expr in constants])
        exprs = [b for _, b in subs] + list(outs)
        ctx["prepare"] = {
            "uses_s": bool(_used(exprs, ["s"])),
            "params": [(i, n) for i, n in enumerate(params) if n in _used(exprs, params)],
            "subs": [(str(a), printer.doprint(b)) for a, b in subs],
            "outs": [printer.doprint(o) for o in outs],
        }
        names = [str(symbol) for symbol, _ in constants]
        funcs, start = [], 0
        for f in self.functions:
            subs, outs = _cse(hoisted[start : start + len(f.outputs)])
            start += len(f.outputs)
            exprs = [b for _, b in subs] + list(outs)
            funcs.append(
                {
                    "name": f.name,
                    "doc": f.doc,
                    "labels": f.labels,
                    "scalar": f.scalar,
                    "uses_ag": bool(_used(exprs, ["ag"])),
                    "state": [(i, n) for i, n in enumerate(state) if n in _used(exprs, state)],
                    "constants": [(i, n) for i, n in enumerate(names) if n in _used(exprs, names)],
                    "subs": [(str(a), printer.doprint(b)) for a, b in subs],
                    "outs": [printer.doprint(o) for o in outs],
                }
            )
        ctx["functions"] = funcs
        ctx["n_constants"] = len(constants)
        ctx["prefix"] = self.spec.name
        ctx["PREFIX"] = self.spec.name.upper()
        return {
            f"{self.spec.name}.h": self.env.get_template("model.h.j2").render(**ctx),
            f"{self.spec.name}.c": self.env.get_template("model.c.j2").render(**ctx),
        }


class LatexGenerator(Generator):
    """EQUATIONS.md: the derived equations in LaTeX, to hold against the paper."""

    def files(self):
        sysm = self.eq.system
        symbol_names = {sp.Symbol(str(d), real=True): r"\dot{" + sp.latex(q) + "}" for q, d in zip(sysm.q, sysm.dq)}
        symbol_names.update({d: r"\ddot{" + sp.latex(q) + "}" for q, d in zip(sysm.q, sysm.ddq)})
        symbol_names[ag] = r"\ddot{x}_g"
        plus = {
            sp.Symbol(str(d) + "_plus", real=True): r"\dot{" + sp.latex(q) + "}^{+}" for q, d in zip(sysm.q, sysm.dq)
        }
        symbol_names.update(plus)

        def tex(expr):
            return sp.latex(expr, symbol_names=symbol_names)

        n = len(sysm.q)
        ddq = sp.Matrix(sysm.ddq)
        eqs_rock = [
            tex(
                sp.Eq(
                    sp.Add(*[sp.collect(self.eq.mass_matrix[i, j], s) * ddq[j] for j in range(n)]), self.eq.forcing[i]
                )
            )
            for i in range(n)
        ]
        ctx = self.context()
        ctx.update(
            rocking=eqs_rock,
            contact=[tex(sp.Eq(d, a)) for d, a in zip(sysm.ddq[1:], self.eq.contact_accel[1:])],
            uplift=tex(self.eq.uplift),
            impact=[tex(sp.Eq(p, sp.factor_terms(sp.cancel(v)))) for p, v in zip(plus, self.eq.impact)],
            energy=tex(self.eq.energy),
            power=tex(self.eq.power),
            critical=tex(self.eq.critical_angle),
        )
        return {"EQUATIONS.md": self.env.get_template("EQUATIONS.md.j2").render(**ctx)}


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


class ManifestGenerator(Generator):
    """manifest.json: what the model is, so a runtime can use it without knowing it."""

    def __init__(self, eq, spec, produced: dict[str, str]):
        super().__init__(eq, spec)
        self.produced = produced

    def files(self):
        ctx = self.context()
        data = {
            "format": FORMAT_VERSION,
            "model": self.spec.name,
            "title": self.spec.title,
            "options": self.eq.options,
            "coordinates": ctx["coordinates"],
            "state": ctx["state"],
            "parameters": [
                {"name": p.name, "unit": p.unit, "doc": p.doc, "valid": p.valid}
                for p in self.spec.all_parameters
                if p.name in ctx["params"]
            ],
            "arguments": [a.name for a in self.args],
            "functions": {
                f.name: {"outputs": len(f.outputs), "scalar": f.scalar, "doc": f.doc} for f in self.functions
            },
            "files": {
                "numpy": "model.py",
                "c_source": f"{self.spec.name}.c",
                "c_header": f"{self.spec.name}.h",
                "c_prefix": self.spec.name,
                "equations": "EQUATIONS.md",
            },
            "sha256": {name: hashlib.sha256(text.encode()).hexdigest() for name, text in sorted(self.produced.items())},
            "sympy": sp.__version__,
            "inputs_sha256": input_hash(self.spec, self.eq.options),
        }
        return {"manifest.json": json.dumps(data, indent=2, sort_keys=True) + "\n"}


BACKENDS = (NumpyGenerator, CGenerator, LatexGenerator)


def generate(eq: Equations, spec) -> dict[str, str]:
    """All files of a model, keyed by file name."""
    out: dict[str, str] = {}
    for backend in BACKENDS:
        out.update(backend(eq, spec).files())
    out.update(ManifestGenerator(eq, spec, dict(out)).files())
    return out
