"""Expressions of a spec, read as data: a small arithmetic grammar turned into SymPy without ``eval``.

SymPy's own parsers (``parse_expr``, ``sympify``) run the text through Python's
``eval``, so a spec could execute code while it is read. Here the text is
parsed by :func:`ast.parse` alone and the tree is walked: only the nodes of
:data:`GRAMMAR` are accepted, and the SymPy expression is built from them with
the same operators ``parse_expr`` would apply, so a spec's expressions mean
what they meant before. Anything else is refused with a :class:`SpecError`
quoting the offending text.

Bounds keep a hostile expression from exhausting the machine: the text's
length, the number of nodes and the depth of the tree, the size of numbers
(``10**10**10`` is refused before it is computed) and of exponents.
"""

from __future__ import annotations

import ast
import math

import sympy as sp

from .names import SpecError, quote

#: Elementary functions an expression may call, with their number of (positional) arguments.
FUNCTIONS = {
    "sin": (sp.sin, 1),
    "cos": (sp.cos, 1),
    "tan": (sp.tan, 1),
    "asin": (sp.asin, 1),
    "acos": (sp.acos, 1),
    "atan": (sp.atan, 1),
    "atan2": (sp.atan2, 2),
    "sinh": (sp.sinh, 1),
    "cosh": (sp.cosh, 1),
    "tanh": (sp.tanh, 1),
    "exp": (sp.exp, 1),
    "log": (sp.log, 1),
    "sqrt": (sp.sqrt, 1),
    "abs": (sp.Abs, 1),
}
#: Named constants.
CONSTANTS = {"pi": sp.pi}

_BINARY = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}
_UNARY = {ast.UAdd: lambda a: +a, ast.USub: lambda a: -a}

#: Longest expression text, most nodes, deepest nesting, largest |exponent|, most bits of an exact number.
MAX_TEXT = 400
MAX_NODES = 200
MAX_DEPTH = 24
MAX_EXPONENT = 64
MAX_BITS = 1024

GRAMMAR = (
    "numbers (int, float), the declared symbols, pi, + - * / ** (unary + -), parentheses and calls "
    f"{', '.join(FUNCTIONS)} with positional arguments"
)

#: What a refused node is, in a message.
_REFUSED = {
    ast.Attribute: "attribute access",
    ast.Subscript: "indexing",
    ast.Lambda: "lambda",
    ast.JoinedStr: "f-strings",
    ast.Compare: "comparisons",
    ast.BoolOp: "and/or",
    ast.IfExp: "conditional expressions",
    ast.NamedExpr: "assignments",
    ast.Starred: "starred arguments",
    ast.Tuple: "tuples",
    ast.List: "lists",
    ast.Dict: "dicts",
    ast.Set: "sets",
}


def _segment(text: str, node: ast.AST) -> str:
    """The source text of ``node`` (the whole text when Python cannot tell)."""
    return ast.get_source_segment(text, node) or text


def _refuse(where: str, what: str, text: str, node: ast.AST | None = None) -> SpecError:
    """The error for ``what`` found in ``text`` (at ``node``)."""
    at = f" ({quote(_segment(text, node))})" if node is not None else ""
    return SpecError(f"{where}: {what} not allowed in {quote(text)}{at}; expressions may use {GRAMMAR}")


def _parse_tree(text: str, where: str) -> ast.expr:
    """The syntax tree of ``text``, its size and depth bounded.

    Raises
    ------
    SpecError
        When the text is too long, not ASCII, does not parse, or its tree is too large or too deep.
    """
    if len(text) > MAX_TEXT:
        raise SpecError(f"{where}: expression of {len(text)} characters, at most {MAX_TEXT} allowed")
    if not (text.isascii() and text.isprintable()):
        raise SpecError(f"{where}: expression {quote(text)} holds characters other than printable ASCII")
    try:
        tree = ast.parse(text, mode="eval").body
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        reason = getattr(exc, "msg", None) or type(exc).__name__
        raise SpecError(f"{where}: cannot parse {quote(text)} ({reason})") from None
    # Depth and size by an explicit stack: the tree of a hostile text must not overflow Python's.
    stack: list[tuple[ast.AST, int]] = [(tree, 1)]
    nodes = 0
    while stack:
        node, depth = stack.pop()
        nodes += 1
        if nodes > MAX_NODES or depth > MAX_DEPTH:
            limit = f"{MAX_NODES} nodes" if nodes > MAX_NODES else f"{MAX_DEPTH} levels of nesting"
            raise SpecError(f"{where}: expression {quote(text)} is too large (at most {limit})")
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node))
    return tree


#: The nodes of the grammar (their operators are checked as they are built).
_NODES = (ast.Constant, ast.Name, ast.BinOp, ast.UnaryOp, ast.Call)


def _check_nodes(tree: ast.expr, text: str, where: str) -> None:
    """Every node of ``tree`` is one of :data:`_NODES`, before any name is looked at.

    Raises
    ------
    SpecError
        Naming the first other node and quoting its text.
    """
    for node in ast.walk(tree):
        if isinstance(node, (ast.operator, ast.unaryop, ast.expr_context)) or isinstance(node, _NODES):
            continue
        if isinstance(node, (ast.keyword, ast.Starred)):
            raise _refuse(where, "keyword or starred arguments", text, node)
        what = _REFUSED.get(type(node), type(node).__name__)
        raise _refuse(where, what, text, node if isinstance(node, ast.expr) else None)


def _check_unknown_names(tree: ast.expr, text: str, where: str, known: dict) -> None:
    """Every name is declared, a constant, or a function in call position.

    Raises
    ------
    SpecError
        Listing the unknown names, as the derivation always did.
    """
    called = {id(n.func) for n in ast.walk(tree) if isinstance(n, ast.Call)}
    unknown = sorted(
        {
            n.id
            for n in ast.walk(tree)
            if isinstance(n, ast.Name) and n.id not in known and n.id not in CONSTANTS and id(n) not in called
        }
    )
    if unknown:
        raise SpecError(
            f"{where}: unknown symbol(s) {', '.join(unknown)} in {quote(text)}; "
            "declare them under [parameters] or [coordinates]"
        )


def _check_number(value: sp.Expr, where: str, text: str) -> sp.Expr:
    """``value`` if it is no exact number of more than :data:`MAX_BITS` bits."""
    if isinstance(value, sp.Rational) and max(abs(value.p).bit_length(), value.q.bit_length()) > MAX_BITS:
        raise SpecError(f"{where}: a number in {quote(text)} is too large (more than {MAX_BITS} bits)")
    return value


def _power(base: sp.Expr, exponent: sp.Expr, where: str, text: str, node: ast.AST) -> sp.Expr:
    """``base ** exponent``, refused before it is computed when the exponent is a large number."""
    if exponent.is_number:
        size = abs(float(exponent)) if exponent.is_real else math.inf
        if not size <= MAX_EXPONENT:
            raise _refuse(where, f"an exponent above {MAX_EXPONENT} in size", text, node)
        if isinstance(base, sp.Rational) and isinstance(exponent, sp.Rational):
            bits = max(abs(base.p).bit_length(), base.q.bit_length()) * size
            if bits > MAX_BITS:
                raise SpecError(f"{where}: a number in {quote(text)} is too large (more than {MAX_BITS} bits)")
    return base**exponent


def _literal(node: ast.Constant, where: str, text: str) -> sp.Expr:
    """A numeric literal, as ``parse_expr`` reads it: an exact ``Integer``, or a ``Float`` of its digits."""
    value = node.value
    if type(value) is int:
        return _check_number(sp.Integer(value), where, text)
    if type(value) is float:
        if not math.isfinite(value):
            raise _refuse(where, "a non-finite number", text, node)
        return sp.Float(_segment(text, node).replace("_", ""))
    kind = "strings" if isinstance(value, (str, bytes)) else f"{type(value).__name__} constants"
    raise _refuse(where, kind, text, node)


def _call(node: ast.Call, build, where: str, text: str) -> sp.Expr:
    """A call of one of :data:`FUNCTIONS`, positional arguments only."""
    name = node.func.id if isinstance(node.func, ast.Name) else None
    if name not in FUNCTIONS:
        raise _refuse(where, "a call of something other than the listed functions", text, node)
    function, arity = FUNCTIONS[name]
    if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
        raise _refuse(where, "keyword or starred arguments", text, node)
    if len(node.args) != arity:
        raise SpecError(f"{where}: {name} takes {arity} argument(s), got {len(node.args)} in {quote(text)}")
    return function(*(build(a) for a in node.args))


def _builder(text: str, where: str, known: dict):
    """The function that turns a node of ``text``'s tree into SymPy (recursion bounded by :data:`MAX_DEPTH`)."""

    def build(node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Constant):
            return _literal(node, where, text)
        if isinstance(node, ast.Name):
            return known[node.id] if node.id in known else CONSTANTS[node.id]
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            left, right = build(node.left), build(node.right)
            if isinstance(node.op, ast.Pow):
                return _check_number(_power(left, right, where, text, node), where, text)
            return _check_number(_BINARY[type(node.op)](left, right), where, text)
        if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            return _UNARY[type(node.op)](build(node.operand))
        if isinstance(node, ast.Call):
            return _call(node, build, where, text)
        if isinstance(node, ast.BinOp):
            hint = " (use ** for powers)" if isinstance(node.op, ast.BitXor) else ""
            raise _refuse(where, f"the operator {type(node.op).__name__}{hint}", text, node)
        raise _refuse(where, _REFUSED.get(type(node), type(node).__name__), text, node)

    return build


def _check_value(expr: sp.Expr, where: str, text: str) -> sp.Expr:
    """``expr`` if it is finite and real: no ``1/0``, ``log(0)``, ``sqrt(-1)`` or overflowing number."""
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan, sp.I):
        raise SpecError(f"{where}: {quote(text)} is not a finite real expression")
    for number in expr.atoms(sp.Number):
        try:
            finite = math.isfinite(float(number))
        except (OverflowError, TypeError):
            finite = False
        if not finite:
            raise SpecError(f"{where}: a number in {quote(text)} is out of the range of a double")
    return expr


def parse_expression(text, where: str, known: dict[str, sp.Symbol]) -> sp.Expr:
    """The SymPy expression of a spec entry, with only ``known`` symbols (and :data:`CONSTANTS`) in scope.

    Parameters
    ----------
    text : str, int or float
        The entry: expression text, or a TOML number.
    where : str
        Where it is, for messages (``body 'mass' position x``).
    known : dict of str to Symbol
        The names in scope.

    Raises
    ------
    SpecError
        Quoting the text and what in it is not allowed.
    """
    if type(text) in (int, float):  # a TOML number: exact, as before
        if not math.isfinite(text):
            raise SpecError(f"{where}: {quote(text)} is not a finite number")
        return _check_value(_check_number(sp.nsimplify(text), where, str(text)), where, str(text))
    if not isinstance(text, str):
        raise SpecError(f"{where}: expected an expression, got {quote(text)}")
    text = text.strip()  # in eval mode, Python refuses leading spaces as an indent
    tree = _parse_tree(text, where)
    _check_nodes(tree, text, where)
    _check_unknown_names(tree, text, where, known)
    return _check_value(_builder(text, where, known)(tree), where, text)
