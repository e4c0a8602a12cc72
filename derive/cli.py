"""Command line of the derivation: ``python -m rocking.derive`` (what ``make derive`` runs).

Examples
--------
python -m rocking.derive                         # every registered variant into rocking.generated
python -m rocking.derive --variant omd           # one variant
python -m rocking.derive --spec my.toml --out models/my   # a user's own spec, from any folder
python -m rocking.derive --check                 # exit 1 if the generated files are stale
python -m rocking.derive --spec my.toml --out models/my --stage-limit 600 --verbose

Each model is derived in a child process, stage by stage (energies, equations of
motion, ..., LaTeX); a stage that runs past its limit of CPU time (``--stage-limit``,
default 60 s) is stopped with a one-line error naming it and the spec's costliest
expression. Before that, an expression whose degree, expanded terms or nesting of
functions is over the bounds of :mod:`rocking.derive.cost` is refused at once.
Stages that take a second or more are printed to stderr as they end
(``--verbose``: every stage); the generated files never depend on it.

Another command line offers the same by calling :func:`main` with its own
``prog`` (``rocking derive ...``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .build import GENERATED, package_init_is_stale, stale_files, write, write_package_init
from .cost import LIMITS
from .spec import SpecError, load_spec, registered_variants, variant_spec
from .watchdog import STAGE_LIMIT, StageLog, build_bounded, failure

PROG = "python -m rocking.derive"
EPILOG = (
    "Each model is derived in a child process, stage by stage; a stage that runs past --stage-limit is stopped "
    "with a one-line error naming it and the spec's costliest expression (exit code 2). Stages that take a second "
    "or more are printed to stderr as they end."
)


def one_line(message) -> str:
    """``message`` on one line of printable characters: an error never spreads over lines or moves the cursor."""
    text = " ".join(str(message).split())
    return "".join(c if c.isprintable() else "?" for c in text)


def parse_options(pairs: list[str]) -> dict:
    """``KEY=VALUE`` pairs of ``--option`` as a dict.

    Raises
    ------
    SpecError
        When a pair has no ``=``.
    """
    opts = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep:
            raise SpecError(f"--option expects KEY=VALUE, got {pair!r}")
        opts[key] = value
    return opts


def make_parser(prog: str = PROG) -> argparse.ArgumentParser:
    """The argument parser, shown under the name ``prog``."""
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0], epilog=EPILOG)
    parser.add_argument("--variant", action="append", help="registered variant to build (repeatable; default: all)")
    parser.add_argument("--spec", type=Path, help="a spec file of your own (needs --out)")
    parser.add_argument("--out", type=Path, help="output folder (default: <name> in the folder of rocking.generated)")
    parser.add_argument(
        "--option", action="append", default=[], metavar="KEY=VALUE", help="derivation option, e.g. impact=velocity"
    )
    parser.add_argument("--check", action="store_true", help="only compare with the files on disk; exit 1 if stale")
    parser.add_argument(
        "--stage-limit",
        type=_seconds,
        default=STAGE_LIMIT,
        metavar="SECONDS",
        help=f"limit of CPU time of each stage of a derivation, in s, 0 for none (default: {STAGE_LIMIT:g}); before "
        "any stage, an expression is refused over degree {LIMITS.degree} in the coordinates and their functions, "
        f"{LIMITS.terms} terms expanded or {LIMITS.nesting} nested functions (docs/variants.md)",
    )
    parser.add_argument(
        "-v", "--verbose", action="store_true", help="print every stage and its time to stderr (default: stages >= 1 s)"
    )
    return parser


def _seconds(text: str) -> float:
    """``--stage-limit``: a number of seconds >= 0."""
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value >= 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a number of seconds >= 0 (0: no limit), got {text!r}")
    return value


def targets(args: argparse.Namespace, parser: argparse.ArgumentParser) -> list[tuple]:
    """``(spec, folder)`` of every model the arguments ask for.

    Raises
    ------
    SpecError
        For a spec that does not load or an unknown variant.
    """
    if args.spec is not None:
        if args.out is None:
            parser.error("--spec needs --out FOLDER")
        return [(load_spec(args.spec), args.out)]
    names = args.variant or registered_variants()
    if args.out is not None and len(names) != 1:
        parser.error("--out takes a single --variant")
    return [(variant_spec(n), args.out or GENERATED / n) for n in names]


def run(specs: list[tuple], options: dict, check: bool, limit: float = STAGE_LIMIT, verbose: bool = False) -> list[str]:
    """Derive each ``(spec, folder)``, write it or compare it, and print one line per model.

    Each derivation runs in a child process, each stage under ``limit`` seconds (0: none;
    :func:`rocking.derive.watchdog.build_bounded`), its stages printed to stderr (every one if ``verbose``).

    Returns
    -------
    list of str
        The stale files (only with ``check``).
    """
    stale = []
    for spec, folder in specs:
        built = build_bounded(spec, options, limit, StageLog(spec.name, verbose))
        if check:
            bad = stale_files(built, folder)
            stale += [str(folder / b) for b in bad]
            status = "stale: " + ", ".join(bad) if bad else "up to date"
        else:
            write(built, folder)
            status = f"written to {folder}"
        print(f"{spec.name:>10}: derived in {built.seconds:.2f} s, {status}")
    return stale


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Run the command line on ``argv`` (default: ``sys.argv[1:]``).

    Parameters
    ----------
    argv : list of str, optional
        The arguments, without the program name.
    prog : str
        The program name that usage and error messages show.

    Returns
    -------
    int
        0 on success, 1 when ``--check`` finds stale files, 2 for a rejected
        spec or option, or a derivation stopped at a stage's time limit
        (argparse's own errors exit with 2 as well).
    """
    parser = make_parser(prog)
    args = parser.parse_args(argv)
    try:
        stale = run(targets(args, parser), parse_options(args.option), args.check, args.stage_limit, args.verbose)
    except SpecError as exc:
        print(f"error: {one_line(exc)}", file=sys.stderr)
        return 2
    except (RecursionError, MemoryError, ArithmeticError, ValueError, TypeError, OSError) as exc:
        # A spec that passed every check but still breaks the derivation: one line, never a traceback.
        print(f"error: {one_line(failure(exc))}", file=sys.stderr)
        return 2
    # The package's __init__.py (its MANIFEST_FORMAT) goes with the models of rocking.generated.
    if args.spec is None and args.out is None:
        if not args.check:
            write_package_init()
        elif package_init_is_stale():
            stale.append(str(GENERATED / "__init__.py"))
    if stale:
        print(f"generated files are stale: {', '.join(stale)}; run the same command without --check", file=sys.stderr)
        return 1
    return 0
