"""The right-hand side of a generated model over a vector of cases, for the lanes of the C batch (lanes.c).

The generated C (``generated/<model>/<model>.c``) writes ``<model>_rocking_accel_prepared`` as straight-line
code: ``const double name = expression;`` lines and ``out[i] = expression;``, of ``+ - * /``, parentheses,
numbers, ``y[i]``, ``cst[i]``, ``ag``, ``sin`` and ``cos``. :func:`vector_rhs` rewrites that body with
``double`` a GCC vector of doubles (one case per element) and ``sin`` / ``cos`` of one argument the project's
vector ``sincos`` (lanes.c): each element then goes through the operations the scalar function applies, in its
order (``-ffp-contract=off``), and differs from it only by the last bits of sin and cos. A body with anything
else (``pow``, ``fmax``, a condition) is refused: the header then says ``LANES_MODEL 0`` and the batch runs
scalar for that model.

The header is written at build time beside the C sources (rocking.sim.cbuild) and is part of the library's
source key: it is derived from the generated C, not stored.
"""

from __future__ import annotations

import re

__all__ = ["FUNCTIONS", "vector_rhs"]

#: The generated functions the lanes evaluate, by the macro that defines each over vectors: the accelerations
#: while rocking (required) and in full contact (optional: without it, full contact is stepped scalar).
FUNCTIONS = {"LANES_DEFINE_RHS": "rocking_accel_prepared", "LANES_DEFINE_CONTACT": "contact_accel_prepared"}

_SIGNATURE = "void {prefix}_{name}(const double *y, double ag, const double *cst, double *out)\n{{\n"
_DEFINE = re.compile(r"const double (\w+) = (.+);")
_OUT = re.compile(r"out\[(\d+)\] = (.+);")
_UNUSED = re.compile(r"\(void\)(ag|y|cst);")
_TOKEN = re.compile(r"\s*(?:(\d+\.\d+(?:e[+-]?\d+)?|\d+)|(\w+)\[(\d+)\]|(sin|cos)\((\w+)\)|(\w+)|([-+*/()]))")


def _body(text: str, prefix: str, name: str) -> list[str] | None:
    """The lines of ``prefix``'s generated function ``name``, or None if the C has no such function."""
    head = _SIGNATURE.format(prefix=prefix, name=name)
    start = text.find(head)
    if start < 0:
        return None
    end = text.find("\n}\n", start)
    return [line.strip() for line in text[start + len(head) : end].splitlines() if line.strip()]


def _expression(expr: str, known: set[str], used: set[int], trig: dict[str, str]) -> str | None:
    """``expr`` over vectors, or None if it holds anything but the straight-line arithmetic above. An expression
    of numbers alone is a double: it is added to a vector of zeros (a vector is not assigned a double)."""
    parts, pos, vector = [], 0, False
    while pos < len(expr):
        m = _TOKEN.match(expr, pos)
        if m is None:
            return None
        number, array, index, func, arg, name, op = m.groups()
        vector |= number is None and op is None
        if number is not None:
            parts.append(number)
        elif array is not None:
            if array not in ("y", "cst"):
                return None
            if array == "cst":
                used.add(int(index))
            parts.append(f"{array}[{index}]")
        elif func is not None:
            if arg not in known:
                return None
            trig.setdefault(arg, f"lanes_{arg}")
            parts.append(f"{trig[arg]}_{'s' if func == 'sin' else 'c'}")
        elif name is not None:
            if name not in known:
                return None
            parts.append(name)
        else:
            parts.append(op)
        pos = m.end()
    return "".join(parts) if vector else f"(VD){{0}} + ({''.join(parts)})"


def _lines(body: list[str], used: set[int]) -> list[str] | None:
    """The vector statements of ``body`` (the constants it reads added to ``used``), or None if refused."""
    known = {"ag"}
    trig: dict[str, str] = {}  # the arguments of sin and cos, in the order met
    out = []
    for line in body:
        if _UNUSED.fullmatch(line):
            continue
        define, store = _DEFINE.fullmatch(line), _OUT.fullmatch(line)
        m = define or store
        if m is None:
            return None
        before = set(trig)
        expr = _expression(m.group(2), known, used, trig)
        if expr is None:
            return None
        # One reduction for both sin and cos of an argument, before its first use.
        out += [
            f"VD {trig[a]}_s, {trig[a]}_c; LANES_SINCOS({a}, &{trig[a]}_s, &{trig[a]}_c);"
            for a in trig
            if a not in before
        ]
        if define:
            known.add(define.group(1))
            out.append(f"const VD {define.group(1)} = {expr};")
        else:
            out.append(f"out[{m.group(1)}] = {expr};")
    return out


def _macro(macro: str, statements: list[str]) -> str:
    return " \\\n".join(
        [
            f"#define {macro}(name, attributes, extra)",
            "    attributes void name(const VD *y, VD ag, const VD *cst, VD *out, extra)",
            "    {",
            "        (void)y, (void)ag, (void)cst;",
        ]
        + [f"        {s}" for s in statements]
        + ["    }"]
    )


def vector_rhs(text: str, prefix: str) -> str:
    """The header lanes.c includes for the model of C source ``text`` and prefix ``prefix``.

    It defines ``LANES_MODEL`` (1 if the rocking accelerations could be written over vectors, else 0) and, if 1,
    ``LANES_CONTACT`` (1 if those of full contact could too), ``LANES_CST_USED(X)`` (``X(i)`` for each constant
    ``cst[i]`` they read) and the macros of :data:`FUNCTIONS`: ``LANES_DEFINE_RHS(name, attributes, extra)``
    defines ``attributes void name(const VD *y, VD ag, const VD *cst, VD *out, extra)`` for the vector type ``VD``
    and the ``LANES_SINCOS`` in scope where it is expanded (``extra``: a parameter that macro may read).
    """
    head = f"/* {prefix}'s accelerations over lanes: written by rocking.sim.lanes_rhs at build time, do not edit. */\n"
    used: set[int] = set()
    macros = {}
    for macro, name in FUNCTIONS.items():
        body = _body(text, prefix, name)
        found = set[int]()
        statements = _lines(body, found) if body is not None else None
        if statements is not None:
            macros[macro] = _macro(macro, statements)
            used |= found
    if "LANES_DEFINE_RHS" not in macros:
        return head + "#define LANES_MODEL 0\n"
    gather = " ".join(f"X({i})" for i in sorted(used))
    return (
        f"{head}#define LANES_MODEL 1\n#define LANES_CONTACT {int('LANES_DEFINE_CONTACT' in macros)}\n"
        f"#define LANES_CST_USED(X) {gather}\n" + "\n".join(macros.values()) + "\n"
    )
