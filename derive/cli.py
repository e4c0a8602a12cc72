"""Command line of the derivation: ``python -m rocking.derive`` (what ``make derive`` runs).

Examples
--------
python -m rocking.derive                         # every registered variant into rocking.generated
python -m rocking.derive --variant omd           # one variant
python -m rocking.derive --spec my.toml --out models/my   # a user's own spec, from any folder
python -m rocking.derive --check                 # exit 1 if the generated files are stale

Another command line offers the same by calling :func:`main` with its own
``prog`` (``rocking derive ...``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .build import GENERATED, build, package_init_is_stale, stale_files, write, write_package_init
from .spec import SpecError, load_spec, registered_variants, variant_spec

PROG = "python -m rocking.derive"


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
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0])
    parser.add_argument("--variant", action="append", help="registered variant to build (repeatable; default: all)")
    parser.add_argument("--spec", type=Path, help="a spec file of your own (needs --out)")
    parser.add_argument("--out", type=Path, help="output folder (default: <name> in the folder of rocking.generated)")
    parser.add_argument(
        "--option", action="append", default=[], metavar="KEY=VALUE", help="derivation option, e.g. impact=velocity"
    )
    parser.add_argument("--check", action="store_true", help="only compare with the files on disk; exit 1 if stale")
    return parser


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


def run(specs: list[tuple], options: dict, check: bool) -> list[str]:
    """Derive each ``(spec, folder)``, write it or compare it, and print one line per model.

    Returns
    -------
    list of str
        The stale files (only with ``check``).
    """
    stale = []
    for spec, folder in specs:
        built = build(spec, options)
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
        spec or option (argparse's own errors exit with 2 as well).
    """
    parser = make_parser(prog)
    args = parser.parse_args(argv)
    try:
        stale = run(targets(args, parser), parse_options(args.option), args.check)
    except SpecError as exc:
        print(f"error: {one_line(exc)}", file=sys.stderr)
        return 2
    except (RecursionError, MemoryError, ArithmeticError, ValueError, TypeError, OSError) as exc:
        # A spec that passed every check but still breaks the derivation: one line, never a traceback.
        print(f"error: the derivation failed ({type(exc).__name__}: {one_line(exc)[:200]})", file=sys.stderr)
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
