"""The ``rocking`` command line."""

from __future__ import annotations

import argparse
import sys

from .model import ModelError, available_models, load_model
from .params import ParameterError


def _cmd_verify(args) -> int:
    from .verify import report, verify

    ok = True
    for name in args.model or ["omd", "block"]:
        model = load_model(name)
        checks = verify(model, n=args.cases, seed=args.seed)
        print(report(model, checks))
        ok &= all(c.ok for c in checks)
    return 0 if ok else 1


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="rocking", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("verify", help="compare the generated code with the hand-written equations of model.md")
    p.add_argument(
        "--model",
        action="append",
        help=f"model name or folder (default: omd and block; installed: {', '.join(available_models())})",
    )
    p.add_argument("--cases", type=int, default=1000, help="random cases per pivot (default 1000)")
    p.add_argument("--seed", type=int, default=0)
    p.set_defaults(func=_cmd_verify)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ParameterError, ModelError) as exc:
        print(f"rocking: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
