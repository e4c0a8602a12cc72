"""Options shared by the commands, and how their values become the Python API's arguments.

The command line passes to the Python API only the options that were given:
an input left out is not passed at all, so the constructor (``Block``,
``Damper``, ``Tuning``, ...) applies its own default and an omitted input
means the same on both sides. Help texts read those defaults from the same
signatures (:func:`python_default`) instead of retyping them.

Flag rule (every command): a flag is the name of the Python parameter it sets,
with ``-`` for ``_`` (``--omega-ratio`` sets ``omega_ratio``, ``--k-m`` sets
``k_m``); the symbols of docs/model.md keep their case there (``--H`` and ``--h``,
``--M`` and ``--m``, ``--Omega`` and ``--omega-g`` are different quantities);
flags that set no model parameter are lower-case words joined by ``-``.
Abbreviated flags are refused, so each option has exactly one spelling.
"""

from __future__ import annotations

import argparse
import inspect
from collections.abc import Callable, Iterable

from ..model.floor import Floor, floor_of
from ..model.params import Block, ParameterError
from ..model.records import STANDARD_GRAVITY

#: Marks a parameter without a default in :func:`python_default`'s answer.
REQUIRED = inspect.Parameter.empty

#: Blocks known by name (``--block NAME``), each the Python call that builds it.
BLOCKS: dict[str, Callable[[], Block]] = {"reference": Block.reference}

#: The block of every command when no block option is given (said in each help).
DEFAULT_BLOCK = "reference"

#: Flags that set the block: by name, by its dimensions (rocking.Block), non-dimensionally (Block.from_nondim).
SI_BLOCK = ("H", "B", "e")
NONDIM_BLOCK = ("p", "lam", "alpha", "e_ratio")


def python_default(func: Callable, name: str):
    """Default of a parameter of the Python API, read from its signature.

    Parameters
    ----------
    func : callable
        Function, bound method or class (a dataclass: its ``__init__``).
    name : str
        Parameter name.

    Returns
    -------
    object
        The default, or :data:`REQUIRED` when the parameter has none.
    """
    return inspect.signature(func).parameters[name].default


def default_text(func: Callable, name: str, unit: str = "") -> str:
    """``"default X unit"`` read from the signature of ``func``, for a help text."""
    value = python_default(func, name)
    if isinstance(value, float):
        value = f"{value:g}"
    return f"default {value}{' ' + unit if unit else ''}"


#: Most numbers a message lists before "and N more".
LISTED = 6


def numbers_text(values, cap: int = LISTED) -> str:
    """``5.242, 5.818 and 3 more``: the first ``cap`` of ``values`` at 4 significant digits, for a message."""
    values = list(values)
    shown = ", ".join(f"{float(v):.4g}" for v in values[:cap])
    return shown + (f" and {len(values) - cap} more" if len(values) > cap else "")


def flag(name: str) -> str:
    """The flag of the Python parameter ``name`` (the module's flag rule)."""
    return "--" + name.replace("_", "-")


def flags(names: Iterable[str]) -> str:
    return ", ".join(flag(n) for n in names)


def given(args: argparse.Namespace, names: Iterable[str]) -> dict:
    """The options among ``names`` that were given, by Python parameter name.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options; argparse leaves an option not given at None.
    names : iterable of str
        Python parameter names (= option dests).

    Returns
    -------
    dict
        ``{name: value}`` of the options given, ready to pass as keyword arguments.
    """
    return {n: getattr(args, n) for n in names if getattr(args, n, None) is not None}


def call_with(func: Callable, values: dict, what: str, *positional, hint: str = ""):
    """``func(*positional, **values)``, refusing first, by their flags, the required parameters not given.

    Without this check a missing required input would be a ``TypeError`` of
    the constructor (a traceback) instead of a one-line message.

    Parameters
    ----------
    func : callable
        The Python API's constructor.
    values : dict
        Keyword arguments: the options given.
    what : str
        What is built, for the message (``"a pulse"``).
    *positional
        Leading positional arguments (e.g. the block of ``from_nondim``).
    hint : str, optional
        Appended to the message.

    Returns
    -------
    object
        ``func(*positional, **values)``.

    Raises
    ------
    ParameterError
        Naming the flags of the required parameters missing, or from ``func``.
    """
    params = list(inspect.signature(func).parameters.values())[len(positional) :]
    missing = [
        p.name
        for p in params
        if p.default is REQUIRED and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) and p.name not in values
    ]
    if missing:
        got = flags(values) or "none of its options"
        raise ParameterError(f"{what} needs {flags(missing)} too (got {got}){hint}")
    return func(*positional, **values)


def acceleration(text: str, name: str) -> float:
    """An acceleration typed as a number of m/s^2 (``4.9``) or of g with a ``g`` suffix (``0.5g``, g =
    :data:`rocking.model.records.STANDARD_GRAVITY`), in m/s^2.

    Raises
    ------
    ParameterError
        Naming the option ``name`` (its flag) and the two forms, for any other text.
    """
    typed = str(text).strip()
    in_g = typed.lower().endswith("g")
    number = typed[:-1] if in_g else typed
    try:
        value = float(number)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{name} takes accelerations in m/s^2 (4.9) or in g with a g suffix (0.5g) (got {text!r})"
        ) from None
    return value * STANDARD_GRAVITY if in_g else value


def add_parser(subparsers, name: str, text: str, description: str | None = None, **kwargs) -> argparse.ArgumentParser:
    """A subcommand's parser: abbreviations refused (one spelling per flag), ``text`` as help and description."""
    return subparsers.add_parser(
        name, help=text, description=description or text[:1].upper() + text[1:] + ".", allow_abbrev=False, **kwargs
    )


# --- the block ------------------------------------------------------------------------------


def describe(block: Block) -> str:
    """``H = 2 m, B = 0.5 m, M = 1000 kg, e = 0.025 m`` of ``block`` (help texts; never retyped)."""
    return f"H = {block.H:g} m, B = {block.B:g} m, M = {block.M:g} kg, e = {block.e:g} m"


def block_help() -> str:
    """Where every command's block comes from, for its description."""
    return (
        f"Block: --block {DEFAULT_BLOCK} unless given ({describe(BLOCKS[DEFAULT_BLOCK]())}, docs/model.md section 9), "
        "or its dimensions --H --B --M [--e] as rocking.Block(H, B, M, e), "
        "or --p with --lam or --alpha [--e-ratio] [--M] as rocking.Block.from_nondim."
    )


def add_block_options(p: argparse.ArgumentParser) -> None:
    """The block options, shared by every command: a named block, its dimensions, or its non-dimensional form."""
    # Where the block comes from is said once, in the command's description (block_help).
    g = p.add_argument_group("block (one way: by name, by its dimensions or non-dimensionally)")
    names = ", ".join(f"{name} ({describe(make())})" for name, make in BLOCKS.items())
    g.add_argument(
        "--block", choices=tuple(BLOCKS), help=f"a block by name: {names}; the default when no block option is given"
    )
    g.add_argument("--H", type=float, help="height, m (with --B and --M)")
    g.add_argument("--B", type=float, help="base width, m")
    g.add_argument(
        "--M",
        type=float,
        help=f"mass, kg (needed with --H and --B; with --p {default_text(Block.from_nondim, 'M', 'kg')})",
    )
    g.add_argument(
        "--e", type=float, help=f"eccentricity of G towards the right corner, m ({default_text(Block, 'e', 'm')})"
    )
    g.add_argument("--p", type=float, help="frequency parameter, rad/s: a block from --p and --lam or --alpha")
    g.add_argument("--lam", type=float, help="slenderness H/B")
    g.add_argument("--alpha", type=float, help="slenderness angle atan(B/H), rad")
    g.add_argument("--e-ratio", type=float, help=f"eccentricity e/B ({default_text(Block.from_nondim, 'e_ratio')})")


def block_from(args: argparse.Namespace) -> Block:
    """The block of the options, built exactly as the Python call the help names.

    Parameters
    ----------
    args : argparse.Namespace
        Options of :func:`add_block_options`.

    Returns
    -------
    Block
        ``BLOCKS[--block]()``; ``Block(H, B, M[, e])`` from the dimensions given;
        ``Block.from_nondim(p, lam | alpha[, e_ratio][, M])``; with no block
        option, the block named :data:`DEFAULT_BLOCK`.

    Raises
    ------
    ParameterError
        The block given more than one way, a required dimension missing, or
        a value out of range.
    """
    named = getattr(args, "block", None)
    si, nondim, mass = given(args, SI_BLOCK), given(args, NONDIM_BLOCK), given(args, ("M",))
    if sum(map(bool, (named, si, nondim))) > 1 or (named and mass):
        raise ParameterError(
            "give the block one way, not both: --block NAME, its dimensions (--H --B --M [--e]) "
            "or non-dimensionally (--p with --lam or --alpha [--e-ratio] [--M])"
        )
    if nondim:
        if "p" not in nondim:
            raise ParameterError("a non-dimensional block needs --p (rad/s) with --lam or --alpha")
        return Block.from_nondim(**nondim, **mass)
    if si or mass:
        return call_with(Block, {**si, **mass}, "a block by its dimensions", hint=f"; or --block {DEFAULT_BLOCK}")
    return BLOCKS[named or DEFAULT_BLOCK]()


# --- the floor ----------------------------------------------------------------------------------

#: What ``--mu`` says, on every command that runs simulations.
MU_HELP = (
    "Coulomb friction of the floor, static (kinetic: --mu-k, default = --mu); default inf: the base never slides "
    "(the paper's assumption)"
)
#: The floor's coefficients by the flags that give them, for the messages of :class:`~rocking.Floor`.
FLOOR_FLAGS = {"mu_s": "--mu", "mu_k": "--mu-k", "e_n": "--e-n"}


def add_floor_options(p: argparse.ArgumentParser) -> None:
    """``--mu``, ``--mu-k`` and ``--e-n``: the floor of every run of the command, as
    ``rocking.Floor(mu, mu_k, e_n)``."""
    g = p.add_argument_group(
        "floor",
        "As rocking.Floor(mu_s=--mu, mu_k=--mu-k, e_n=--e-n), dimensionless (docs/model.md sections 15 and 16).",
    )
    g.add_argument("--mu", type=float, metavar="MU", help=MU_HELP + "; in (0, inf]")
    g.add_argument("--mu-k", type=float, metavar="MU_K", help="kinetic friction of the floor, in (0, --mu]")
    g.add_argument(
        "--e-n",
        type=float,
        metavar="E_N",
        help="normal restitution of a landing after flight (docs/model.md section 16), in [0, 1]; "
        + default_text(Floor, "e_n")
        + ": plastic",
    )


def floor_from(args: argparse.Namespace) -> Floor | None:
    """The :class:`~rocking.Floor` of ``--mu``, ``--mu-k`` and ``--e-n``; ``None`` when none is given (the paper's
    floor, plastic landings).

    Raises
    ------
    ParameterError
        Naming the flag (``--mu``, ``--mu-k``, ``--e-n``) and its range.
    """
    chosen = given(args, ("mu", "mu_k", "e_n"))
    if not chosen:
        return None
    try:
        floor = floor_of(None, chosen.get("mu"), chosen.get("mu_k"))
        return Floor(floor.mu_s, floor.mu_k, chosen["e_n"]) if "e_n" in chosen else floor
    except ParameterError as exc:
        text = str(exc).replace("mu_k is the kinetic friction beside mu=: give mu", "--mu-k needs --mu")
        text = text.replace("(0, mu_s]", "(0, --mu]")
        raise ParameterError(named_as_flag(FLOOR_FLAGS, text)) from None


# --- model variants ------------------------------------------------------------------------------


def params_from(items: Iterable[str] | None) -> dict:
    """``NAME=VALUE`` strings of ``--param`` as a dict of floats.

    Parameters
    ----------
    items : iterable of str or None
        The ``--param`` values.

    Returns
    -------
    dict
        ``{name: float(value)}``.

    Raises
    ------
    ParameterError
        A malformed item, a name given twice or a value that is not a number.
    """
    params = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise ParameterError(f"--param takes NAME=VALUE (got {item!r})")
        if name in params:
            raise ParameterError(f"--param {name} given twice")
        try:
            params[name] = float(value)
        except ValueError:
            raise ParameterError(f"--param {name} must be a number (got {value!r})") from None
    return params


def flags_of(parser: argparse.ArgumentParser) -> dict[str, str]:
    """The long flag of each option of ``parser`` by its keyword (``vertical_ratio`` -> ``--vertical-ratio``)."""
    flags = {}
    for action in parser._actions:
        long = [s for s in action.option_strings if s.startswith("--")]
        if long:
            flags[action.dest] = long[0]
    return flags


def named_as_flag(flags: dict[str, str], message: str) -> str:
    """``message`` of a check, its first word written as the flag that gives it where that word is an option's
    keyword (``vertical_ratio must be ...`` -> ``--vertical-ratio must be ...``): a user is told the option typed,
    not a name inside the package."""
    word, sep, rest = message.partition(" ")
    keyword = word.rstrip(":")
    if sep and keyword in flags:
        return flags[keyword] + word[len(keyword) :] + sep + rest
    return message
