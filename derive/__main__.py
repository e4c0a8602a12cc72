"""Command line: ``python -m derive`` (what ``make derive`` runs).

Examples
--------
python -m derive                         # every registered variant into generated/
python -m derive --variant omd           # one variant
python -m derive --spec my.toml --out models/my   # a user's own spec
python -m derive --check                 # exit 1 if generated/ is stale
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .build import GENERATED, build, stale_files, write, write_package_init
from .spec import SpecError, load_spec, registered_variants, variant_spec


def _options(pairs: list[str]) -> dict:
    opts = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep:
            raise SpecError(f"--option expects KEY=VALUE, got {pair!r}")
        opts[key] = value
    return opts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m derive", description=__doc__.splitlines()[0])
    parser.add_argument("--variant", action="append", help="registered variant to build (repeatable; default: all)")
    parser.add_argument("--spec", type=Path, help="a spec file of your own (needs --out)")
    parser.add_argument("--out", type=Path, help="output folder (default: generated/<name>)")
    parser.add_argument(
        "--option", action="append", default=[], metavar="KEY=VALUE", help="derivation option, e.g. impact=velocity"
    )
    parser.add_argument("--check", action="store_true", help="only compare with the files on disk; exit 1 if stale")
    args = parser.parse_args(argv)
    try:
        opts = _options(args.option)
        if args.spec is not None:
            if args.out is None:
                parser.error("--spec needs --out FOLDER")
            specs = [(load_spec(args.spec), args.out)]
        else:
            names = args.variant or registered_variants()
            if args.out is not None and len(names) != 1:
                parser.error("--out takes a single --variant")
            specs = [(variant_spec(n), args.out or GENERATED / n) for n in names]
        stale = []
        for spec, folder in specs:
            built = build(spec, opts)
            if args.check:
                bad = stale_files(built, folder)
                stale += [str(folder / b) for b in bad]
                status = "stale: " + ", ".join(bad) if bad else "up to date"
            else:
                write(built, folder)
                status = f"written to {folder}"
            print(f"{spec.name:>10}: derived in {built.seconds:.2f} s, {status}")
    except SpecError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.spec is None and args.out is None and not args.check:
        write_package_init()
    if stale:
        print("generated files are stale; run `make derive`", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
