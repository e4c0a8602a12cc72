"""Model specifications: a rocking block and the bodies it carries, as data.

A spec is a TOML file (see ``derive/variants/*.toml``). It names the internal
coordinates of the attached bodies, their parameters, the bodies with their
positions in the block frame, the springs and dashpots, and the impact law of
each internal coordinate. The rocking block itself is common to every model:
height ``H``, base ``B``, mass ``M``, centroidal inertia ``I_G``, eccentricity
``e`` and gravity ``g``; its rocking angle ``theta`` is always the first
coordinate.

The block frame has its origin at the centre of the base, ``x`` to the right,
``y`` up; at ``theta = 0`` it coincides with the frame that translates with the
ground. Units are SI.

Everything is checked here, before any derivation starts. A spec is data
from a stranger: nothing in it is ever executed. Expressions are read by
:mod:`rocking.derive.expressions` (a small grammar, no ``eval``), names and
free text are held to the rules of :mod:`rocking.derive.names`.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

import sympy as sp

from .cost import check_spec_cost
from .expressions import parse_expression
from .names import NAME_PATTERN, SpecError, check_model_name, check_symbol, check_text, quote

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the same parser, from PyPI
    import tomli as tomllib

#: Parameters of the rocking block, shared by every model, in argument order.
BLOCK_PARAMETERS = (
    ("M", "kg", "block mass", "> 0"),
    ("I_G", "kg m^2", "centroidal moment of inertia of the block", "> 0"),
    ("B", "m", "base width", "> 0"),
    ("H", "m", "height", "> 0"),
    ("e", "m", "eccentricity of the centroid G (positive towards A')", "|e| < B/2"),
    ("g", "m/s^2", "gravity", "> 0"),
)

IMPACT_LAWS = ("momentum", "velocity")
INERTIA_OPTIONS = ("free", "homogeneous")
_RESERVED = {"theta", "s", "t", "ag", "agy", "x_g", "y_g"} | {p[0] for p in BLOCK_PARAMETERS}
#: Largest spec file read, in bytes: a spec is a few dozen lines.
MAX_SPEC_BYTES = 64 * 1024
#: Most coordinates, parameters, bodies and elements of each kind a spec may declare.
MAX_ENTRIES = 32

__all__ = ["SpecError", "Spec", "Parameter", "Body", "Element", "Stop", "parse_spec", "load_spec", "variant_spec"]


@dataclass(frozen=True)
class Parameter:
    """A model parameter: its symbol name, unit, meaning and valid range."""

    name: str
    unit: str
    doc: str
    valid: str = ">= 0"


@dataclass(frozen=True)
class Body:
    """A body carried by the block.

    ``position`` is the body's centre of mass in the block frame, ``angle`` its
    rotation relative to the block (for its own rotary inertia).
    """

    name: str
    mass: sp.Expr
    position: tuple[sp.Expr, sp.Expr]
    inertia: sp.Expr = sp.Integer(0)
    angle: sp.Expr = sp.Integer(0)


@dataclass(frozen=True)
class Element:
    """A linear spring (``coefficient`` is a stiffness, ``measure`` a stretch)
    or dashpot (``coefficient`` a damping, ``measure`` whose rate it resists)."""

    name: str
    coefficient: sp.Expr
    measure: sp.Expr
    acts_on: str


#: Sides of a stop: ``upper`` acts while ``travel > gap``, ``lower`` while ``travel < -gap``.
STOP_SIDES = {"both": (1, -1), "upper": (1,), "lower": (-1,)}
#: Contact laws of a stop's pads (docs/model.md section 11): the keys each needs besides gap and stiffness.
STOP_LAWS = {"kelvin-voigt": ("damping",), "hunt-crossley": ("exponent", "damping_factor")}
#: Least approach speed of a Hunt-Crossley pad, in the travel's unit per second, unless its stop
#: declares ``approach_floor``: below it the law's damping ``~ 1 / v_in`` would make the
#: equations as stiff as the contact is slow (docs/model.md section 11).
HC_APPROACH_FLOOR = 1e-3


@dataclass(frozen=True)
class Stop:
    """End stops on a travel of the attached bodies (docs/model.md section 11): compliant bumpers.

    Beyond the gap, the penetration ``delta = sigma travel - gap`` (``sigma = +1``
    for the upper stop, ``-1`` for the lower one) loads a pad while it pushes; inside
    the gap the stop does nothing. ``law`` ``"kelvin-voigt"``: the pad stores
    ``stiffness delta^2 / 2`` and dissipates ``damping ddelta^2 / 2`` (force
    ``max(0, stiffness delta + damping ddelta)``). ``"hunt-crossley"``: it stores
    ``stiffness delta^(n+1) / (n+1)`` (``n`` the ``exponent``) and dissipates
    ``stiffness delta^n chi ddelta^2 / (2 v_in)``, ``chi`` the ``damping_factor`` (that of a
    restitution ``e_b`` is the root of ``chi (1 + e_b) = ln((1 + chi) / (1 - chi e_b))``),
    ``v_in`` the approach speed of the contact, at least ``approach_floor`` (force
    ``max(0, stiffness delta^n (1 + chi ddelta / v_in))``); ``damping`` is then 0.
    """

    name: str
    gap: sp.Expr
    stiffness: sp.Expr
    damping: sp.Expr
    travel: sp.Expr
    sides: tuple[int, ...]
    acts_on: str
    law: str = "kelvin-voigt"
    exponent: sp.Expr = sp.Integer(1)
    damping_factor: sp.Expr = sp.Integer(0)
    approach_floor: float = HC_APPROACH_FLOOR


@dataclass(frozen=True)
class Spec:
    """A complete model specification."""

    name: str
    title: str
    coordinates: tuple[str, ...]
    parameters: tuple[Parameter, ...]
    bodies: tuple[Body, ...]
    springs: tuple[Element, ...]
    dashpots: tuple[Element, ...]
    impact: dict[str, str] = field(default_factory=dict)
    source: str = ""
    stops: tuple[Stop, ...] = ()
    friction: bool = False
    flight: bool = False

    @property
    def all_parameters(self) -> tuple[Parameter, ...]:
        """Block parameters first, then the model's own, in argument order."""
        block = tuple(Parameter(*p) for p in BLOCK_PARAMETERS)
        return block + self.parameters


def _expr(text, where: str, known: dict[str, sp.Symbol]) -> sp.Expr:
    """Parse ``text`` with only the declared symbols in scope, as data (:func:`parse_expression`)."""
    return parse_expression(text, where, known)


def _table(value, where: str) -> dict:
    """``value`` if it is a TOML table."""
    if not isinstance(value, dict):
        raise SpecError(f"{where} must be a table, got {quote(value)}")
    return value


def _list(value, where: str) -> list:
    """``value`` if it is a list of at most :data:`MAX_ENTRIES` entries."""
    if not isinstance(value, list):
        raise SpecError(f"{where} must be a list, got {quote(value)}")
    if len(value) > MAX_ENTRIES:
        raise SpecError(f"{where} has {len(value)} entries, at most {MAX_ENTRIES} allowed")
    return value


def _require(table: dict, key: str, where: str):
    if key not in table:
        raise SpecError(f"{where}: missing required key {key!r}")
    return table[key]


def _check_keys(table: dict, allowed: set[str], where: str) -> None:
    extra = sorted(set(table) - allowed)
    if extra:
        shown = ", ".join(k if NAME_PATTERN.fullmatch(k) and len(k) <= 40 else quote(k) for k in extra[:10])
        raise SpecError(f"{where}: unknown key(s) {shown}; allowed: {', '.join(sorted(allowed))}")


#: Keys of the top-level table of a spec.
_SPEC_KEYS = {
    "name",
    "title",
    "coordinates",
    "parameters",
    "bodies",
    "springs",
    "dashpots",
    "stops",
    "impact",
    "ground",
}


def _model_name(data: dict) -> str:
    """The spec's ``name``, an ASCII identifier that no file, module or C name of the model collides with.

    Raises
    ------
    SpecError
        When it is missing, not an identifier, or reserved.
    """
    return check_model_name(_require(data, "name", "spec"))


def _check_symbol_name(n, model: str) -> None:
    """A coordinate or parameter name must be an identifier the block and the generated code leave free.

    Raises
    ------
    SpecError
        When it is not.
    """
    if isinstance(n, str) and n in _RESERVED:
        raise SpecError(f"spec: {quote(n)} is reserved for the block or the derivation")
    check_symbol(n, model)


def _derived_names(coords: tuple) -> dict[str, str]:
    """The names the derivation gives each coordinate's velocity, acceleration and velocity after an impact.

    Returns
    -------
    dict
        Each derived name, with what it is (for messages).
    """
    derived: dict[str, str] = {}
    for q in ("theta",) + tuple(coords):
        for name, what in ((f"d{q}", "velocity"), (f"dd{q}", "acceleration"), (f"d{q}_plus", "velocity after impact")):
            derived.setdefault(name, f"the {what} of coordinate {q!r}")
    return derived


def _declared_names(coords: tuple, params_table: dict, model: str) -> list[str]:
    """Coordinates then parameters, each checked, none declared twice nor equal to a derived name.

    Raises
    ------
    SpecError
        Naming the first bad name, or when a name is declared twice.
    """
    names = list(coords) + list(params_table)
    for n in names:
        _check_symbol_name(n, model)
    if len(set(names)) != len(names):
        raise SpecError("spec: a name is declared twice among coordinates and parameters")
    derived = _derived_names(coords)
    for n in names:
        if n in derived:
            raise SpecError(f"spec: {quote(n)} is {derived[n]} (the derivation names d<q>, dd<q>, d<q>_plus)")
    for n, what in derived.items():
        # A derived name is a C local and a Python argument too: 'ouble' would give the velocity 'double'.
        try:
            check_symbol(n, model)
        except SpecError as exc:
            reason = str(exc).removeprefix("spec: ")
            raise SpecError(f"spec: {what} would be named {quote(n)}: {reason}; rename the coordinate") from None
    return names


def _parameters(params_table: dict) -> tuple[Parameter, ...]:
    """The model's own parameters from the ``[parameters.<name>]`` tables, in their order.

    Raises
    ------
    SpecError
        For an unknown key in a table.
    """
    parameters = []
    for pname, ptab in params_table.items():
        where = f"parameters.{pname}"
        _check_keys(_table(ptab, where), {"unit", "doc", "valid"}, where)
        parameters.append(
            Parameter(
                pname,
                check_text(ptab.get("unit", ""), f"{where} unit", "unit"),
                check_text(ptab.get("doc", ""), f"{where} doc", "doc"),
                check_text(ptab.get("valid", ">= 0"), f"{where} valid", "valid"),
            )
        )
    return tuple(parameters)


def _symbols(names: list[str]) -> dict[str, sp.Symbol]:
    """The symbols in scope of every expression: the declared names and the block's parameters."""
    known = {n: sp.Symbol(n, real=True) for n in names}
    known.update({p[0]: sp.Symbol(p[0], real=True) for p in BLOCK_PARAMETERS})
    return known


def _body(i: int, btab: dict, known: dict[str, sp.Symbol]) -> Body:
    """The ``i``-th ``[[bodies]]`` table as a :class:`Body`.

    Raises
    ------
    SpecError
        For an unknown or missing key, a position that is not two
        expressions, a bad expression or a negative numeric mass or inertia.
    """
    where = f"bodies[{i}]"
    _check_keys(_table(btab, where), {"name", "mass", "position", "inertia", "angle"}, where)
    bname = check_text(_require(btab, "name", where), f"{where} name", "label")
    where = f"body {bname!r}"
    pos = _require(btab, "position", where)
    if not (isinstance(pos, list) and len(pos) == 2):
        raise SpecError(f"{where}: position must be a list of two expressions [x, y]")
    mass = _expr(_require(btab, "mass", where), f"{where} mass", known)
    inertia = _expr(btab.get("inertia", 0), f"{where} inertia", known)
    for label, value in (("mass", mass), ("inertia", inertia)):
        if value.is_number and value < 0:
            raise SpecError(f"{where}: {label} must be >= 0, got {value}")
    return Body(
        bname,
        mass,
        (_expr(pos[0], f"{where} position x", known), _expr(pos[1], f"{where} position y", known)),
        inertia,
        _expr(btab.get("angle", 0), f"{where} angle", known),
    )


def _bodies(tables: list, known: dict[str, sp.Symbol]) -> tuple[Body, ...]:
    """The ``[[bodies]]`` tables, each checked, their names unique.

    Raises
    ------
    SpecError
        For a bad body, or two bodies with the same name.
    """
    bodies = tuple(_body(i, btab, known) for i, btab in enumerate(_list(tables, "spec: bodies")))
    body_names = [b.name for b in bodies]
    if len(set(body_names)) != len(body_names):
        raise SpecError("spec: two bodies have the same name")
    return bodies


def _element(kind: str, i: int, etab: dict, keys: tuple[str, str], bodies: list[str], known) -> Element:
    """The ``i``-th table of ``kind`` (springs or dashpots) as an :class:`Element`.

    ``keys`` are the keys of its coefficient and of its measure.

    Raises
    ------
    SpecError
        For an unknown or missing key, a bad expression or an unknown body.
    """
    coef_key, measure_key = keys
    where = f"{kind}[{i}]"
    _check_keys(_table(etab, where), {"name", coef_key, measure_key, "acts_on"}, where)
    ename = check_text(etab.get("name", f"{kind}{i}"), f"{where} name", "label")
    where = f"{kind[:-1]} {ename!r}"
    acts_on = _require(etab, "acts_on", where)
    if not isinstance(acts_on, str) or acts_on not in bodies:
        raise SpecError(f"{where}: acts on unknown body {quote(acts_on)}; bodies are {', '.join(bodies) or 'none'}")
    return Element(
        ename,
        _expr(_require(etab, coef_key, where), f"{where} {coef_key}", known),
        _expr(_require(etab, measure_key, where), f"{where} {measure_key}", known),
        acts_on,
    )


def _elements(data: dict, kind: str, keys: tuple[str, str], bodies: list[str], known) -> tuple[Element, ...]:
    """The tables of ``kind`` (springs or dashpots), each checked; ``keys`` as for :func:`_element`."""
    tables = _list(data.get(kind, []), f"spec: {kind}")
    return tuple(_element(kind, i, etab, keys, bodies, known) for i, etab in enumerate(tables))


def _stop(i: int, table: dict, bodies: list[str], coords: tuple, known) -> Stop:
    """The ``i``-th table of ``stops`` as a :class:`Stop`.

    Raises
    ------
    SpecError
        For an unknown or missing key, a bad expression, an unknown body or side, or a
        travel that moves with no attached coordinate.
    """
    where = f"stops[{i}]"
    keys = {"name", "gap", "stiffness", "damping", "travel", "sides", "acts_on", "law"}
    keys |= {"exponent", "damping_factor", "approach_floor"}
    _check_keys(_table(table, where), keys, where)
    name = check_text(table.get("name", f"stops{i}"), f"{where} name", "label")
    where = f"stop {name!r}"
    acts_on = _require(table, "acts_on", where)
    if not isinstance(acts_on, str) or acts_on not in bodies:
        raise SpecError(f"{where}: acts on unknown body {quote(acts_on)}; bodies are {', '.join(bodies) or 'none'}")
    sides = table.get("sides", "both")
    if not isinstance(sides, str) or sides not in STOP_SIDES:
        raise SpecError(f"{where}: unknown sides {quote(sides)}; choose one of {', '.join(STOP_SIDES)}")
    travel = _expr(_require(table, "travel", where), f"{where} travel", known)
    if not {str(a) for a in travel.free_symbols} & set(coords):
        raise SpecError(f"{where}: travel {quote(str(travel))} moves with no coordinate of {', '.join(coords)}")
    law = table.get("law", "kelvin-voigt")
    if not isinstance(law, str) or law not in STOP_LAWS:
        raise SpecError(f"{where}: unknown law {quote(law)}; choose one of {', '.join(STOP_LAWS)}")
    own = {k for laws in STOP_LAWS.values() for k in laws} | {"approach_floor"}
    allowed = set(STOP_LAWS[law]) | ({"approach_floor"} if law == "hunt-crossley" else set())
    extra = sorted((own - allowed) & set(table))
    if extra:
        raise SpecError(
            f"{where}: {', '.join(extra)} is not a key of the {law} law; it takes {', '.join(sorted(allowed))}"
        )
    fields = {k: _expr(_require(table, k, where), f"{where} {k}", known) for k in ("gap", "stiffness", *STOP_LAWS[law])}
    return Stop(
        name,
        fields["gap"],
        fields["stiffness"],
        fields.get("damping", sp.Integer(0)),
        travel,
        STOP_SIDES[sides],
        acts_on,
        law,
        fields.get("exponent", sp.Integer(1)),
        fields.get("damping_factor", sp.Integer(0)),
        _approach_floor(table.get("approach_floor", HC_APPROACH_FLOOR), where),
    )


def _approach_floor(value, where: str) -> float:
    """A Hunt-Crossley stop's least approach speed: a number > 0."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < float("inf"):
        raise SpecError(f"{where}: approach_floor must be a number > 0 (got {quote(value)})")
    return float(value)


def _impact_laws(table: dict, coords: tuple) -> dict[str, str]:
    """The impact law of every coordinate, in coordinate order (``momentum`` unless the table says otherwise).

    Raises
    ------
    SpecError
        For a law given to a name that is not a coordinate, or an unknown law.
    """
    impact = dict(_table(table, "spec: impact"))
    for c in coords:
        impact.setdefault(c, "momentum")
    for c, law in impact.items():
        if c not in coords:
            raise SpecError(f"impact: {quote(c)} is not a coordinate; coordinates are {', '.join(coords)}")
        if not isinstance(law, str) or law not in IMPACT_LAWS:
            raise SpecError(f"impact.{c}: unknown law {quote(law)}; choose one of {', '.join(IMPACT_LAWS)}")
    return {c: impact[c] for c in coords}


def _ground(table: dict) -> tuple[bool, bool]:
    """``[ground] friction`` and ``flight``: whether the model also gets the phases of a floor with friction
    (docs/model.md section 15) and those of flight and landing (section 16), two booleans.

    Flight needs friction: its takeoff is where the floor's normal force of a friction phase reaches 0, and a
    landing is an impact with friction.
    """
    _check_keys(table, {"friction", "flight"}, "spec: ground")
    values = []
    for key in ("friction", "flight"):
        value = table.get(key, False)
        if not isinstance(value, bool):
            raise SpecError(f"spec: ground {key} must be true or false, not {quote(str(value))}")
        values.append(value)
    if values[1] and not values[0]:
        raise SpecError("spec: ground flight = true needs friction = true (takeoff and landing are the floor's)")
    return values[0], values[1]


def parse_spec(data: dict, source: str = "") -> Spec:
    """Build a checked :class:`Spec` from the parsed TOML tables.

    Parameters
    ----------
    data : dict
        The spec's tables, as a TOML parser returns them.
    source : str
        The spec's text, kept for the hash of the generated files.

    Raises
    ------
    SpecError
        With a message naming the offending entry.
    """
    _check_keys(_table(data, "spec"), _SPEC_KEYS, "spec")
    name = _model_name(data)
    coords = tuple(_list(data.get("coordinates", []), "spec: coordinates"))
    params_table = _table(data.get("parameters", {}), "spec: parameters")
    if len(params_table) > MAX_ENTRIES:
        raise SpecError(f"spec: {len(params_table)} parameters, at most {MAX_ENTRIES} allowed")
    names = _declared_names(coords, params_table, name)
    parameters = _parameters(params_table)
    known = _symbols(names)
    bodies = _bodies(data.get("bodies", []), known)
    body_names = [b.name for b in bodies]
    ground = _ground(_table(data.get("ground", {}), "spec: ground"))
    spec = Spec(
        name=name,
        title=check_text(data.get("title", name), "spec: title", "title"),
        coordinates=coords,
        parameters=parameters,
        bodies=bodies,
        springs=_elements(data, "springs", ("stiffness", "stretch"), body_names, known),
        dashpots=_elements(data, "dashpots", ("damping", "rate_of"), body_names, known),
        impact=_impact_laws(data.get("impact", {}), coords),
        source=source,
        stops=tuple(
            _stop(i, table, body_names, coords, known)
            for i, table in enumerate(_list(data.get("stops", []), "spec: stops"))
        ),
        friction=ground[0],
        flight=ground[1],
    )
    _check_coordinates_used(spec)
    check_spec_cost(spec)  # before any other work on the expressions
    _check_stops_nonnegative(spec)
    return spec


def nonnegative(expr: sp.Expr, parameters) -> bool:
    """Whether SymPy shows ``expr`` >= 0 for every value of ``parameters`` in their valid ranges.

    Only the ranges ``> 0`` and ``>= 0`` are understood; any other symbol may take any real value.
    """
    known = {p.name: p.valid for p in parameters}
    signs = {
        sym: sp.Dummy(sym.name, positive=True) if known.get(sym.name) == "> 0" else sp.Dummy(sym.name, nonnegative=True)
        for sym in expr.free_symbols
        if known.get(sym.name) in ("> 0", ">= 0")
    }
    return bool(sp.sympify(expr).xreplace(signs).is_nonnegative)


def _ranges(expr: sp.Expr, parameters) -> str:
    """The declared valid range of every symbol of ``expr``, for a message (``L > 0, x: a coordinate``)."""
    valid = {p.name: p.valid for p in parameters}
    shown = []
    for name in sorted(str(sym) for sym in expr.free_symbols):
        rule = valid.get(name, "a coordinate")
        shown.append(f"{name} {rule}" if rule[:1] in "<>" else f"{name}: {rule}")
    return ", ".join(shown) or "no symbols"


def _check_stops_nonnegative(spec: Spec) -> None:
    """A stop's gap, stiffness and its law's own fields must be >= 0 for every parameter in its declared valid range.

    A negative gap puts the bumper inside the free travel, a negative stiffness or damping makes it
    release energy: the runtime's bounds (docs/simulation.md, rule 4) assume neither; nor does a
    Hunt-Crossley pad's negative damping factor.

    Raises
    ------
    SpecError
        Naming the stop, the field, the expression and the ranges it was read with.
    """
    for stop in spec.stops:
        for field_name in ("gap", "stiffness", *STOP_LAWS[stop.law]):
            expr = getattr(stop, field_name)
            if not nonnegative(expr, spec.all_parameters):
                raise SpecError(
                    f"stop {stop.name!r} {field_name}: {quote(str(expr))} is not shown >= 0 for every value in the "
                    f'declared valid ranges ({_ranges(expr, spec.all_parameters)}); declare valid = "> 0" or '
                    '">= 0" for its parameters, or write it so that it cannot be negative'
                )


def _check_coordinates_used(spec: Spec) -> None:
    """Every internal coordinate must move a body or stretch a spring."""
    used = set()
    for expr in [e for b in spec.bodies for e in (*b.position, b.angle)] + [el.measure for el in spec.springs]:
        used |= {str(a) for a in expr.free_symbols}
    missing = [c for c in spec.coordinates if c not in used]
    if missing:
        raise SpecError(
            f"spec {spec.name!r}: coordinate(s) {', '.join(missing)} appear in no energy "
            "(no body position, body angle or spring depends on them)"
        )


def load_spec(path: str | Path) -> Spec:
    """Read and check a spec file."""
    from rocking.model.records import input_refusal  # the one check of every input file of rocking

    path = Path(path)
    if not path.is_file():
        raise SpecError(f"spec file not found: {path}")
    refused = input_refusal(path)
    if refused:
        raise SpecError(f"{path}: {refused}")
    try:
        raw = path.read_bytes()
        if len(raw) > MAX_SPEC_BYTES:
            raise SpecError(f"{path}: {len(raw)} bytes, a spec holds at most {MAX_SPEC_BYTES}")
        text = raw.decode("utf-8")
        data = tomllib.loads(text)
    except (OSError, UnicodeDecodeError) as exc:
        raise SpecError(f"{path}: cannot be read as UTF-8 text ({type(exc).__name__})") from None
    except (tomllib.TOMLDecodeError, RecursionError) as exc:
        raise SpecError(f"{path}: not valid TOML ({exc})") from None
    return parse_spec(data, source=text)


VARIANTS_DIR = Path(__file__).parent / "variants"


def registered_variants() -> list[str]:
    """Names of the variants shipped in ``derive/variants``, sorted."""
    return sorted(p.stem for p in VARIANTS_DIR.glob("*.toml"))


def variant_spec(name: str) -> Spec:
    """The shipped spec called ``name``."""
    known = registered_variants()
    if name not in known:
        raise SpecError(f"unknown variant {name!r}; registered variants: {', '.join(known)}")
    return load_spec(VARIANTS_DIR / f"{name}.toml")
