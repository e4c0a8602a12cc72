"""The ``rocking`` command line."""

from __future__ import annotations

import argparse
import json
import sys

from ..model.loading import ModelError, available_models, load_model
from ..model.params import Block, Damper, ParameterError
from ..model.pulse import OneSinePulse
from ..sim.run import BACKENDS, simulate
from .study import add_block_options, add_study_commands, block_from


def _cmd_verify(args) -> int:
    from ..reference.verify import report, verify

    ok = True
    for name in args.model or ["omd", "block"]:
        model = load_model(name)
        checks = verify(model, n=args.cases, seed=args.seed)
        print(report(model, checks))
        ok &= all(c.ok for c in checks)
    return 0 if ok else 1


def _damper(args, block: Block) -> Damper | dict | None:
    if args.param:
        values = {}
        for pair in args.param:
            name, sep, value = pair.partition("=")
            try:
                values[name] = float(value)
            except ValueError:
                raise ParameterError(f"--param expects NAME=NUMBER (got {pair!r})") from None
            if not sep:
                raise ParameterError(f"--param expects NAME=NUMBER (got {pair!r})")
        return values
    if args.no_damper or (args.gamma is None and args.m is None):
        return None
    if args.gamma is not None:
        return Damper.from_nondim(
            block, gamma=args.gamma, T_m=args.T_m, omega_ratio=args.omega_ratio, zeta=args.zeta, h=args.h
        )
    return Damper(m=args.m, k_m=args.k_m, c=args.c, h=args.h)


def _pulse(args, block: Block) -> OneSinePulse:
    if args.a_g is not None or args.omega_g is not None:
        if args.a_g is None or args.omega_g is None:
            raise ParameterError("give both --a-g and --omega-g (SI pulse), or --beta and --Omega")
        return OneSinePulse(a_g=args.a_g, omega_g=args.omega_g, psi=args.psi)
    if args.beta is None or args.Omega is None:
        raise ParameterError("a pulse is needed: --beta and --Omega, or --a-g and --omega-g")
    return OneSinePulse.from_nondim(block, beta=args.beta, Omega=args.Omega, psi=args.psi)


def _cmd_simulate(args) -> int:
    block = block_from(args)
    damper = _damper(args, block)
    pulse = _pulse(args, block)
    cases = {"with damper" if damper else "block alone": damper}
    if args.compare and damper is not None:
        cases["block alone"] = None
    responses = {
        label: simulate(
            block,
            d,
            pulse,
            model=args.model if d is not None else None,
            backend=args.backend,
            rtol=args.rtol,
            t_max=args.t_max,
            record=bool(args.plot),
        )
        for label, d in cases.items()
    }
    if args.json:
        payload = {
            "block": block.as_params(),
            "model": args.model,
            "damper": (damper.as_params() if hasattr(damper, "as_params") else damper) if damper else None,
            "pulse": {
                "a_g": pulse.a_g,
                "omega_g": pulse.omega_g,
                "psi": pulse.psi,
                "beta": pulse.beta(block),
                "Omega": pulse.Omega(block),
            },
            "responses": {label: r.summary() for label, r in responses.items()},
        }
        print(json.dumps(payload, indent=2))
    else:
        print(
            f"block H={block.H:g} m B={block.B:g} m e={block.e:g} m "
            f"(alpha={block.alpha:.4f} rad, p={block.p:.4f} rad/s); "
            f"pulse beta={pulse.beta(block):.4g} Omega={pulse.Omega(block):.4g} (a_g={pulse.a_g:.4g} m/s2, "
            f"omega_g={pulse.omega_g:.4g} rad/s, psi={pulse.psi:g})"
        )
        for label, r in responses.items():
            verdict = f"OVERTURNS at t = {r.t_overturn:.4f} s" if r.overturned else "survives"
            print(
                f"  {label}: {verdict}; theta_max/alpha = {r.theta_max / block.alpha:.4f}, x_max = {r.x_max:.4g} m, "
                f"{r.uplifts} uplift(s), {r.impacts} impact(s), ended at t = {r.t_end:.3f} s ({r.status})"
            )
    if args.plot:
        from ..plot.response import plot_responses

        path = plot_responses(
            responses, block.alpha, args.plot, title=f"beta = {pulse.beta(block):.3g}, Omega = {pulse.Omega(block):.3g}"
        )
        print(f"figure written to {path}", file=sys.stderr)
    return 0


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

    p = sub.add_parser("simulate", help="response of a block (with or without damper) to a one-sine pulse")
    add_block_options(p)
    g = p.add_argument_group("damper (SI or non-dimensional; none given: bare block)")
    g.add_argument("--m", type=float, help="mass [kg]")
    g.add_argument("--k_m", type=float, default=0.0, help="stiffness [N/m]")
    g.add_argument("--c", type=float, default=0.0, help="damping [N s/m]")
    g.add_argument("--h", type=float, default=0.05, help="guide height above the top [m] (default 0.05)")
    g.add_argument("--gamma", type=float, help="mass ratio m/M")
    g.add_argument("--T_m", type=float, help="damper period [s]")
    g.add_argument("--omega-ratio", type=float, help="omega_m / p")
    g.add_argument("--zeta", type=float, default=0.05, help="damping ratio (default 0.05)")
    g.add_argument("--no-damper", action="store_true", help="ignore damper options: the bare block")
    g.add_argument("--model", help="model variant by name or generated folder (default: omd, or block without damper)")
    g.add_argument(
        "--param", action="append", metavar="NAME=VALUE", help="a parameter of the variant's bodies (repeatable)"
    )
    g = p.add_argument_group("pulse")
    g.add_argument("--beta", type=float, help="amplitude ratio a_g / (g tan alpha)")
    g.add_argument("--Omega", type=float, help="frequency ratio omega_g / p")
    g.add_argument("--a-g", type=float, help="amplitude [m/s2]")
    g.add_argument("--omega-g", type=float, help="circular frequency [rad/s]")
    g.add_argument("--psi", type=float, default=0.0, help="phase [rad] (default 0)")
    g = p.add_argument_group("run and output")
    g.add_argument("--backend", choices=BACKENDS, default="auto")
    g.add_argument("--rtol", type=float, default=1e-8)
    g.add_argument("--t-max", type=float, help="end time [s] (default: 15 s after the pulse)")
    g.add_argument("--json", action="store_true", help="machine-readable result on stdout")
    g.add_argument("--plot", metavar="FILE", help="figure of theta/alpha, x and the ground acceleration")
    g.add_argument("--compare", action="store_true", help="also run the block alone, on the same axes")
    p.set_defaults(func=_cmd_simulate)
    add_study_commands(sub)
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
