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

__all__ = ["FUNCTION", "vector_rhs"]

#: The generated function the lanes evaluate (the accelerations while rocking).
FUNCTION = "rocking_accel_prepared"

_SIGNATURE = "void {prefix}_{name}(const double *y, double ag, const double *cst, double *out)\n{{\n"
_DEFINE = re.compile(r"const double (\w+) = (.+);")
_OUT = re.compile(r"out\[(\d+)\] = (.+);")
_TOKEN = re.compile(r"\s*(?:(\d+\.\d+(?:e[+-]?\d+)?|\d+)|(\w+)\[(\d+)\]|(sin|cos)\((\w+)\)|(\w+)|([-+*/()]))")


def _body(text: str, prefix: str) -> list[str] | None:
    """The lines of ``prefix``'s generated rocking accelerations, or None if the C has no such function."""
    head = _SIGNATURE.format(prefix=prefix, name=FUNCTION)
    start = text.find(head)
    if start < 0:
        return None
    end = text.find("\n}\n", start)
    return [line.strip() for line in text[start + len(head) : end].splitlines() if line.strip()]


def _expression(expr: str, known: set[str], used: set[int], trig: dict[str, str]) -> str | None:
    """``expr`` over vectors, or None if it holds anything but the straight-line arithmetic above."""
    parts, pos = [], 0
    while pos < len(expr):
        m = _TOKEN.match(expr, pos)
        if m is None:
            return None
        number, array, index, func, arg, name, op = m.groups()
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
    return "".join(parts)


def _lines(body: list[str]) -> tuple[list[str], set[int]] | None:
    """The vector statements of ``body`` and the constants it reads, or None if refused."""
    known, used = {"ag"}, set[int]()
    trig: dict[str, str] = {}  # the arguments of sin and cos, in the order met
    out = []
    for line in body:
        if line == "(void)ag;":
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
    return out, used


def vector_rhs(text: str, prefix: str) -> str:
    """The header lanes.c includes for the model of C source ``text`` and prefix ``prefix``.

    It defines ``LANES_MODEL`` (1 if the rocking accelerations could be written over vectors, else 0) and, if 1,
    ``LANES_CST_USED(X)`` (``X(i)`` for each constant ``cst[i]`` the function reads) and the macro
    ``LANES_DEFINE_RHS(name, attributes, extra)``, which defines ``attributes void name(const VD *y, VD ag,
    const VD *cst, VD *out, extra)`` for the vector type ``VD`` and the ``LANES_SINCOS`` in scope where it is
    expanded (``extra``: a parameter that macro may read).
    """
    body = _body(text, prefix)
    lines = _lines(body) if body is not None else None
    head = f"/* {prefix}_{FUNCTION} over lanes: written by rocking.sim.lanes_rhs at build time, do not edit. */\n"
    if lines is None:
        return head + "#define LANES_MODEL 0\n"
    statements, used = lines
    macro = " \\\n".join(
        [
            "#define LANES_DEFINE_RHS(name, attributes, extra)",
            "    attributes void name(const VD *y, VD ag, const VD *cst, VD *out, extra)",
            "    {",
        ]
        + [f"        {s}" for s in statements]
        + ["    }"]
    )
    gather = " ".join(f"X({i})" for i in sorted(used))
    return f"{head}#define LANES_MODEL 1\n#define LANES_CST_USED(X) {gather}\n{macro}\n"
