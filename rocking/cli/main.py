"""The ``rocking`` command: ``simulate``, ``verify`` and ``derive`` here, the studies in :mod:`.study`.

Every command builds the Python API's objects from the options that were
given and nothing else (:mod:`.options`), so ``rocking simulate --H 1.8 --B 0.45
--M 300 ...`` simulates ``rocking.Block(H=1.8, B=0.45, M=300)``, with the same
defaults. Bad parameters end with a one-line message naming the parameter and
its valid range, and exit code 2.
"""

from __future__ import annotations

import argparse
import difflib
import json
import math
import os
import re
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..model.loading import ModelError, available_models, load_model
from ..model.motion import PULSE_TYPES, MavroeidisPapageorgiou, SampledMotion
from ..model.params import (
    BUMPER_DAMPING_RATIO,
    BUMPER_DEPTH,
    BUMPER_LAWS,
    BUMPER_RESTITUTION,
    BUMPER_STIFFNESS,
    RANGES,
    Damper,
    ParameterError,
    Stops,
    check_in_range,
)
from ..model.pulse import OneSinePulse
from ..model.records import UNITS, paired_vertical, read_record
from ..model.vertical import Vertical
from ..sim.accuracy import CHECKS
from ..sim.boundary import SUMMARY
from ..sim.cbuild import CBuildError
from ..sim.history import HISTORY_FORMATS
from ..sim.history import write as write_history
from ..sim.problem import SimulationError
from ..sim.run import NAMES, simulate
from ..sim.stroke import mass_past_edge
from ..study.config import Tuning, versions
from ..study.kinds import KINDS
from . import claim_process
from .options import (
    add_block_options,
    add_floor_options,
    add_parser,
    block_from,
    block_help,
    call_with,
    default_text,
    flag,
    flags,
    flags_of,
    floor_from,
    given,
    named_as_flag,
    params_from,
    python_default,
)
from .rerun import apply_config
from .study import add_study_commands, warnings_in_one_line

DESCRIPTION = (
    "A rigid block rocking on the ground with an oscillating mass damper on its top: "
    f"one response (simulate), the studies ({', '.join(KINDS)}; demo runs several, redraw draws them again), "
    "the generated code against the paper (verify) and its derivation (derive). "
    "Units SI; rocking COMMAND --help for a command's options."
)

#: Damper options of simulate: in SI (rocking.Damper), or relative to the block (Damper.from_nondim); --h is both's.
SI_DAMPER = ("m", "k_m", "c")
NONDIM_DAMPER = ("gamma", "T_m", "omega_ratio", "zeta")
#: Options of a damper relative to the block that default to the studies' (rocking.Tuning's own defaults).
TUNING_DEFAULTS = ("omega_ratio", "zeta", "h")

#: The options that run a study's tiles on Dask (rocking.Execution's): without them, a command never uses Dask.
DASK_OPTIONS = ("scheduler", "dask_workers")

#: Top-level packages of the derive extra (pyproject.toml): their absence is a missing install, not a bug.
DERIVE_EXTRA = ("sympy", "jinja2", "tomli")
DERIVE_INSTALL = 'pip install "rocking[derive]"'


# --- verify ---------------------------------------------------------------------------------------


def _cmd_verify(args) -> int:
    from ..reference.verify import BY_HAND, CASES, SEEDS, check_count, report, verify

    # Checked by their flags before any model loads (verify() would name its keywords n and seed).
    options: dict[str, Any] = {"n": check_count("--cases", args.cases, CASES)} if args.cases is not None else {}
    options.update({"seed": check_count("--seed", args.seed, SEEDS)} if args.seed is not None else {})
    ok = True
    for name in args.model or BY_HAND:
        model = load_model(name)
        checks = verify(model, **options)
        print(report(model, checks))
        ok &= all(c.ok for c in checks)
    return 0 if ok else 1


def _add_verify(sub) -> None:
    from ..reference.verify import BY_HAND, CASES, SEEDS, verify

    p = add_parser(sub, "verify", "compare the generated code with the hand-written equations of docs/model.md")
    p.add_argument(
        "--model",
        action="append",
        help=f"model name or folder, repeatable (default: {', '.join(BY_HAND)}; "
        f"installed: {', '.join(available_models())})",
    )
    p.add_argument(
        "--cases",
        type=int,
        help=f"random cases per pivot, {CASES.rule()} ({default_text(verify, 'n')})",
    )
    p.add_argument(
        "--seed", type=int, help=f"seed of the random cases, {SEEDS.rule()} ({default_text(verify, 'seed')})"
    )
    p.set_defaults(func=_cmd_verify)


# --- simulate -------------------------------------------------------------------------------------


def _damper(args, block) -> Damper | dict | None:
    """The damper of the options: None (bare block), a Damper (SI or relative), or a variant's parameters."""
    params = params_from(args.param)
    si, nondim, options = given(args, SI_DAMPER), given(args, NONDIM_DAMPER), given(args, (*SI_DAMPER, *NONDIM_DAMPER))
    h = given(args, ("h",))
    if args.no_damper:
        return None
    if params:
        if options or h:
            raise ParameterError(
                f"{flags({**options, **h})}: damper options of the omd model; "
                "with --param give the model's own parameters as --param NAME=VALUE"
            )
        return params
    if si and nondim:
        raise ParameterError(
            "give the damper in SI (--m --k-m [--c] [--h]) or relative to the block "
            "(--gamma with --T-m or --omega-ratio [--zeta] [--h]), not both"
        )
    if nondim:
        if "gamma" not in nondim:  # said here, where the options given are not yet mixed with the defaults
            raise ParameterError(f"a damper relative to the block needs --gamma too (got {flags({**nondim, **h})})")
        values = {**_tuning_defaults(nondim), **nondim, **h}
        return call_with(Damper.from_nondim, values, "a damper relative to the block", block)
    if si:
        return call_with(Damper, {**si, **h}, "a damper in SI")
    if h:
        raise ParameterError("--h is the damper's guide height: give the damper (--gamma or --m) or --no-damper")
    return None


def _tuning_defaults(nondim: dict) -> dict:
    """The studies' defaults (:class:`rocking.Tuning`) of the options of a damper relative to the block, so that
    ``--gamma 0.05`` alone is the damper a study runs; none for ``omega_ratio`` when ``--T-m`` sets the tuning."""
    names = [n for n in TUNING_DEFAULTS if not (n == "omega_ratio" and "T_m" in nondim)]
    return {name: python_default(Tuning, name) for name in names}


#: End-stop options of simulate, rocking.Stops(L, k_b, c_b): each replaces the value of --stops (Stops.at_edges).
STOP_OPTIONS = ("L", "k_b", "c_b")
#: Options of the Hunt-Crossley pads (--bumper-law hunt-crossley, which they imply): Stops(n=, e_b=).
HC_OPTIONS = ("n_b", "e_b")


def _with_stops(args, block, damper):
    """``damper`` with the end stops of the options (``--stops``, ``--L``, ``--k-b``, ``--c-b``, ``--bumper-law``,
    ``--n-b``, ``--e-b``), or as it is."""
    own, hc = given(args, STOP_OPTIONS), given(args, HC_OPTIONS)
    law = given(args, ("bumper_law",))
    if not (args.stops or own or hc or law):
        return damper
    named = flags([*(["stops"] if args.stops else []), *own, *law, *hc])
    if not isinstance(damper, Damper) or damper.m == 0.0:
        raise ParameterError(
            f"{named}: end stops of the damper's guide: give the damper (--gamma or --m); "
            "a variant (--param) takes L, k_b, c_b as --param NAME=VALUE"
        )
    _check_stop_options({**own, **hc})
    law = law.get("bumper_law", "hunt-crossley" if hc else "kelvin-voigt")
    if hc and law != "hunt-crossley":
        raise ParameterError(f"{flags(hc)}: parameters of the Hunt-Crossley pads (--bumper-law hunt-crossley)")
    stops = _stops(block, damper, own, law, {"n" if k == "n_b" else k: v for k, v in hc.items()})
    if args.model not in (None, stops.model):
        raise ParameterError(f"{named}: end stops run on the model {stops.model} (got --model {args.model})")
    return replace(damper, stops=stops)


def _check_stop_options(values: dict) -> None:
    """Refuse, by their flags, end-stop values out of their ranges (``RANGES``), before any is used: a negative
    ``--k-b`` would otherwise reach the square root of the default ``c_b``."""
    for name, value in values.items():
        check_in_range(flag(name), value, name)


def _stops(block, damper: Damper, own: dict, law: str = "kelvin-voigt", hc: dict | None = None) -> Stops:
    """``Stops.at_edges(block, damper, law=law, **hc)`` with the ``own`` values of ``L``, ``k_b``, ``c_b`` in place
    of its; without ``c_b``, the Kelvin-Voigt pads' damping ratio on the bumpers' ``k_b``."""
    if law == "hunt-crossley":
        edges = call_with(Stops.at_edges, {"law": law, **(hc or {})}, "end stops", block, damper)
        values = {"L": edges.L, "k_b": edges.k_b, "law": law, "n": edges.n, "e_b": edges.e_b, **own}
        return call_with(Stops, values, "end stops")
    values = {**Stops.at_edges(block, damper).as_params(), **own}
    if "c_b" not in own:
        values["c_b"] = 2 * BUMPER_DAMPING_RATIO * math.sqrt(values["k_b"] * damper.m)
    return call_with(Stops, values, "end stops")


def _model_of(args, damper) -> str | None:
    """The model a response with ``damper`` runs on: None for the block alone."""
    if damper is None:
        return None
    return args.model or (damper.model if isinstance(damper, Damper) else "omd")


#: The pulses of ``--pulse``: the family's class and its fixed arguments (docs/model.md section 12).
PULSES = {family.replace("_", "-"): made for family, made in PULSE_TYPES.items()}
#: The shape options of each family besides --sign (their dests), and the class's parameter each sets.
SHAPE_OPTIONS = {"sine": {"psi": "psi"}, "mp": {"gamma_mp": "gamma_mp", "nu": "nu"}}


def _pulse(args, block):
    """The pulse of the options: its family (--pulse), SI (the class) or relative to the block (its from_nondim)."""
    si, nondim = given(args, ("a_g", "omega_g")), given(args, ("beta", "Omega"))
    if args.vertical is not None:
        raise ParameterError("--vertical FILE is a record's vertical component: it goes with --motion")
    family = args.pulse or "sine"
    cls, fixed = PULSES[family]
    own = SHAPE_OPTIONS.get(family, {})
    foreign = given(args, [k for options in SHAPE_OPTIONS.values() for k in options if k not in own])
    if foreign:
        raise ParameterError(f"{flags(foreign)}: not an option of --pulse {family}")
    if family == "mp" and args.gamma_mp is None:
        raise ParameterError("--pulse mp needs --gamma-mp too (its oscillations, > 1)")
    shape = {**fixed, **{own[k]: v for k, v in given(args, own).items()}, **given(args, ("sign",))}
    if args.vertical_ratio is not None:
        shape["vertical"] = call_with(Vertical, _vertical_options(args), "a vertical component")
    elif args.vertical_phase is not None:
        raise ParameterError("--vertical-phase needs --vertical-ratio (the vertical amplitude over the horizontal)")
    if si and nondim:
        raise ParameterError("give the pulse as --beta and --Omega, or in SI as --a-g and --omega-g, not both")
    if si:
        return call_with(cls, {**si, **shape}, "a pulse in SI")
    if not nondim:
        raise ParameterError("a pulse is needed: --beta and --Omega, or --a-g and --omega-g")
    return call_with(cls.from_nondim, {**nondim, **shape}, "a pulse", block)


def _vertical_options(args) -> dict:
    """``Vertical``'s arguments from ``--vertical-ratio`` and ``--vertical-phase``."""
    phase = {} if args.vertical_phase is None else {"phase": args.vertical_phase}
    return {"ratio": args.vertical_ratio, **phase}


#: Options of a pulse, refused with --motion (a record sets the motion).
PULSE_OPTIONS = (
    "pulse",
    "beta",
    "Omega",
    "a_g",
    "omega_g",
    "psi",
    "gamma_mp",
    "nu",
    "vertical_ratio",
    "vertical_phase",
)


def _motion(args) -> SampledMotion:
    """The record of ``--motion FILE`` (``--unit`` or its header for text files), times ``--scale`` or scaled to
    ``--pga``."""
    foreign = given(args, PULSE_OPTIONS)
    if foreign:
        raise ParameterError(f"{flags(foreign)}: options of a pulse; --motion gives a recorded motion")
    record = read_record(args.motion, args.unit)
    a_v = None if args.vertical is None else _vertical_record(args, record)
    motion = SampledMotion(record.acceleration, dt=record.dt, a_v=a_v, **given(args, ("sign",)))
    if args.scale is not None and args.pga is not None:
        raise ParameterError("give --scale (a factor) or --pga (a target peak, m/s2), not both")
    if args.pga is not None:
        return motion.scaled_to_pga(args.pga)
    return motion.scaled(args.scale) if args.scale is not None else motion


def _vertical_record(args, record) -> np.ndarray:
    """The samples of ``--vertical FILE`` at the horizontal record's times, as a suite pairs them
    (:func:`rocking.model.records.paired_vertical`: the same dt, 0 after a shorter record's end, cut at the
    horizontal record's)."""
    return paired_vertical(record, read_record(args.vertical, args.unit), f"--vertical {args.vertical}")


def _motion_text(block, motion) -> str:
    """What the summary says of the excitation: a pulse's ratios and shape, or a record's length and peak."""
    if isinstance(motion, SampledMotion):
        return (
            f"record of {motion.n} samples at dt={motion.dt:g} s, "
            f"PGA={motion.pga:.4g} m/s2 ({motion.pga / block.g:.3g} g) at scale {motion.scale:.4g}, "
            f"sign={motion.sign:+d}{'' if motion.a_v is None else ', with a vertical record'}"
        )
    return (
        f"pulse beta={motion.beta(block):.4g} Omega={motion.Omega(block):.4g} (a_g={motion.a_g:.4g} m/s2, "
        f"omega_g={motion.omega_g:.4g} rad/s, {_pulse_text(motion)}, sign={motion.sign:+d}{_vertical_text(motion)})"
    )


def _vertical_text(pulse) -> str:
    """What the summary says of a pulse's vertical component (nothing without one)."""
    v = pulse.vertical
    return "" if v is None else f", vertical ratio={v.ratio:g} phase={v.phase:g} rad (> 0 up)"


def _pulse_text(pulse) -> str:
    """The family of a pulse and its shape parameters, as the summary prints them."""
    if isinstance(pulse, OneSinePulse):
        return f"psi={pulse.psi:g}"
    if isinstance(pulse, MavroeidisPapageorgiou):
        return f"mp, gamma_mp={pulse.gamma_mp:g}, nu={pulse.nu:g}"
    return pulse.family.replace("_", "-")


def _payload(block, damper, pulse, model, responses, models) -> dict:
    """What simulate --json prints; ``models``: each response's model (None: the block alone)."""
    if isinstance(pulse, SampledMotion):
        excitation = {
            "family": "sampled",
            "samples": pulse.n,
            "dt": pulse.dt,
            "scale": pulse.scale,
            "pga": pulse.pga,
            "sign": pulse.sign,
        }
    else:
        shape = {"psi": pulse.psi} if isinstance(pulse, OneSinePulse) else {"family": pulse.family}
        if isinstance(pulse, MavroeidisPapageorgiou):
            shape.update(gamma_mp=pulse.gamma_mp, nu=pulse.nu)
        excitation = {
            "a_g": pulse.a_g,
            "omega_g": pulse.omega_g,
            **shape,
            "sign": pulse.sign,
            "beta": pulse.beta(block),
            "Omega": pulse.Omega(block),
        }
    damper_params = (damper.as_params() if hasattr(damper, "as_params") else damper) if damper else None
    payload = {
        "block": block.as_params(),
        "model": model or (damper.model if isinstance(damper, Damper) else "omd" if damper else "block"),
        "damper": damper_params,
        "pulse": excitation,
        "responses": {
            label: {**r.summary(), "mass_past_edge": mass_past_edge(r, block.B / 2, models[label])}
            for label, r in responses.items()
        },
    }
    return {**payload, "units": _units(payload), "versions": versions()}


def _units(payload: dict) -> dict:
    """The units of the numbers of a ``simulate --json`` payload, by name ("1": a ratio, a count, a flag)."""
    names = {k for part in ("block", "damper", "pulse") for k in (payload[part] or {})}
    units = {name: RANGES[name].unit or "1" for name in names if name in RANGES}
    own = {"I_G": "kg m^2", "dt": "s", "pga": "m/s^2", "scale": "1", "samples": "1", "sign": "1"}
    units.update({k: v for k, v in own.items() if k in names})
    units.update({f.name: f.unit or "1" for f in SUMMARY}, mass_past_edge="1")
    return dict(sorted(units.items()))


def _print_summary(block, pulse, responses, models) -> None:
    """The text of simulate: the block and the motion, then a line per response (``models``: each one's model)."""
    print(
        f"block H={block.H:g} m B={block.B:g} m M={block.M:g} kg e={block.e:g} m "
        f"(alpha={block.alpha:.4f} rad, p={block.p:.4f} rad/s); {_motion_text(block, pulse)}"
    )
    for label, r in responses.items():
        print(
            f"  {label}: {_verdict(r)}; theta_max/alpha = {r.theta_max / block.alpha:.4f}, x_max = {r.x_max:.4g} m, "
            f"{r.uplifts} uplift(s), {r.impacts} impact(s){_stops_text(r, models[label])}, "
            f"ended at t = {r.t_end:.3f} s ({_status_text(r)})"
        )
        if r.slides:  # a floor with friction (docs/model.md section 15): the base slipped
            print(
                f"  {label}: the base slid: peak u_max = {r.u_max * 1e3:.4g} mm, residual u_end = "
                f"{r.u_end * 1e3:.4g} mm, {r.slides} slip episode(s)"
            )
        if r.flights:  # a flight model (docs/model.md section 16): the base left the floor and landed
            print(
                f"  {label}: the base flew: {r.flights} flight(s), {r.flight_time:.4g} s off the floor in all, "
                f"highest base point {r.jump_max * 1e3:.4g} mm above it"
            )
        if r.status == "flight":
            print(
                f"  {label}: FLIGHT: the floor's normal force reached 0 at t = {r.t_end:.4f} s, the base may leave "
                "the ground; this model has no flight functions (docs/model.md sections 14, 16), the results stop "
                "there"
            )
        if r.status in NO_VERDICT:
            print(f"  {label}: NO VERDICT: {_no_verdict_text(r)}")
        if r.status == "below_barrier":
            print(
                f"  {label}: safe at t_max = {r.t_end:g} s: the energy left is below the least on the way to "
                "overturning (docs/simulation.md rule 5); theta_max and x_max are those until then"
            )
        if mass_past_edge(r, block.B / 2, models[label]):
            print(f"  {label}: {_past_edge_text(r, block, models[label])}")
        if r.sensitive:
            print(
                f"  {label}: SENSITIVE to the tolerance: the check's {r.check_runs} runs disagree "
                f"(theta_max/alpha {r.theta_max_low / block.alpha:.4f} to {r.theta_max_high / block.alpha:.4f}, "
                f"{r.overturned_fraction:.0%} overturned); this is the tightest run's (docs/simulation.md, "
                "Sensitivity to the tolerance)"
            )


#: Statuses of a run that ended with its verdict: overturned, at rest, bounded for good or below the barrier
#: (docs/simulation.md rule 4). Any other run was cut short (or left the model's scope, flight): it has no verdict.
VERDICT_STATUSES = ("overturned", "rest", "bounded", "below_barrier")

#: Why a run cut short has no verdict, by status: the bound it reached (formatted with the run's settings and
#: its end, ``t_end``) and the way to a verdict.
NO_VERDICT = {
    "t_max": ("the run reached t_max = {t_max:g} s", "follow it longer (a larger --t-max)"),
    "max_events": (
        "the run reached max_events = {max_events} uplifts and impacts",
        "follow it further in Python (rocking.simulate(..., max_events=N))",
    ),
    "max_steps": (
        "the run's work passed max_steps = {max_steps} (docs/simulation.md rule 5)",
        "a larger --rtol (or --history-dt) takes less work",
    ),
    "failed": ("the integrator failed at t = {t_end:g} s (step size underflow)", "check the inputs"),
    "jammed": (
        "a landing at t = {t_end:g} s had no consistent impulse, neither sticking nor sliding (docs/model.md "
        "section 16)",
        "the rigid landing laws have no answer there: a verdict needs a compliant contact",
    ),
}


def _status_text(response) -> str:
    """The status of the summary line, ``bounded`` with what it means where it appears."""
    if response.status != "bounded":
        return response.status
    return (
        "bounded: from then on the energy left can no longer change the verdict, theta_max or x_max; "
        "impacts counted until then"
    )


def _verdict(response) -> str:
    """The verdict word of the summary: ``OVERTURNS at t = ...``, ``survives`` only for a run that ended with its
    verdict, else ``no verdict (STATUS)``."""
    if response.overturned:
        return f"OVERTURNS at t = {response.t_overturn:.4f} s"
    if response.status in VERDICT_STATUSES:
        return "survives"
    return f"no verdict ({response.status})"


def _no_verdict_text(response) -> str:
    """Why a run cut short by a bound (or a failure) says nothing of overturning, and how to get a verdict."""
    reason, way = NO_VERDICT[response.status]
    return (
        f"{reason.format(**response.inputs.settings, t_end=response.t_end)} before overturning, rest or a final "
        f"bound (docs/simulation.md rule 4); overturning later is not excluded: {way}"
    )


def _stops_text(response, model: str | None) -> str:
    """``, N stop contact(s), bumper force max F N`` for a model with end stops (parameter ``L``), else nothing."""
    if model is None or "L" not in load_model(model).own_parameters:
        return ""
    # + 0.0: a force that never left 0 is -0.0 in a run whose pads never pushed, printed "-0".
    return f", {response.stop_contacts} stop contact(s), bumper force max {response.bumper_force_max + 0.0:.4g} N"


def _past_edge_text(response, block, model: str) -> str:
    """The warning of a response whose mass ran past the block's edge, with the way out."""
    text = (
        f"WARNING: the damper's mass went past the block's edge (x_max = {response.x_max:.4g} m > "
        f"B/2 = {block.B / 2:.4g} m): a guide on the block ends there, "
        "so this response holds on paper only"
    )
    if "L" in load_model(model).own_parameters:
        return text + " (through its bumpers: stiffer ones, --k-b, or a shorter stroke, --L)"
    return text + "; --stops puts end stops at the edges"


#: Keywords of the functions ``rocking simulate`` calls, as the messages of their checks name them (first word),
#: and the flags that give them: a user is told the option typed, not a name inside the package.
SIMULATE_FLAGS = {
    "target": "--pga",
    "factor": "--scale",
    "ratio": "--vertical-ratio",
    "phase": "--vertical-phase",
    "record_dt": "--history-dt",
    "dt must be in [t_max": "--history-dt must be in [t_max",
}


def simulate_flags(message: str) -> str:
    """``message`` of a check ``rocking simulate`` runs, its keywords written as the command's flags."""
    for word, option in SIMULATE_FLAGS.items():
        if message.startswith(word if " " in word else word + " "):
            message = option + message[len(word) :]
            break
    return re.sub(r"\b(T_m|omega_ratio)(?= or |=| \(|\))", lambda m: "--" + m.group(1).replace("_", "-"), message)


def _cmd_simulate(args) -> int:
    with warnings_in_one_line(args.command):
        try:
            return _simulate(args)
        except ParameterError as exc:
            raise ParameterError(simulate_flags(str(exc))) from None


def _simulate(args) -> int:
    block = block_from(args)
    damper = _with_stops(args, block, _damper(args, block))
    pulse = _motion(args) if args.motion else _pulse(args, block)
    cases = {"with damper" if damper else "block alone": damper}
    if args.compare and damper is not None:
        cases["block alone"] = None
    histories = _history_files(args.history, list(cases))
    _check_outputs(args.plot, histories)
    run = given(args, ("backend", "rtol", "t_max", "check"))
    if args.history_dt is not None:
        run["record_dt"] = args.history_dt
    if args.early_verdict and args.follow_to_rest:
        raise ParameterError("--early-verdict ends a run before rest: not with --follow-to-rest")
    # The same run whatever the outputs asked for: followed to rest unless --early-verdict (docs/simulation.md,
    # rule 4), so that the summary, the figure and the history tell of one motion.
    run["early_verdict"] = args.early_verdict
    floor = floor_from(args)
    if floor is not None:
        run["floor"] = floor
    record = bool(args.plot or args.history)
    responses = {}
    models = {label: _model_of(args, d) for label, d in cases.items()}
    for label, d in cases.items():
        model = {"model": args.model} if d is not None and args.model is not None else {}
        responses[label] = simulate(block, d, pulse, record=record, **run, **model)
    if args.json:
        payload = _payload(block, damper, pulse, args.model, responses, models)
        if floor is not None and (floor.slides or floor.e_n):  # the paper's floor is said by leaving it out
            payload["floor"] = {k: v for k, v in floor.settings().items() if math.isfinite(v)}  # JSON has no inf
            payload["units"].update(dict.fromkeys(payload["floor"], "1"))
        print(json.dumps(payload, indent=2))
    else:
        _print_summary(block, pulse, responses, models)
    if args.plot:
        from ..plot.response import plot_responses

        with _writing("--plot", args.plot):
            source = Path(args.motion).name if args.motion else ""
            path = plot_responses(
                responses, block, args.plot, damper=damper, model=args.model, motion=pulse, record=source
            )
        print(f"figure written to {path}", file=sys.stderr)
    for label, path in histories.items():
        with _writing("--history", path):
            write_history(responses[label], path, args.history_dt)
        print(f"history ({label}) written to {path}", file=sys.stderr)
    return 0


@contextmanager
def _writing(option: str, path: str | Path) -> Iterator[None]:
    """Turn an ``OSError`` of writing ``path`` into a one-line error naming ``option`` and the path."""
    try:
        yield
    except OSError as exc:
        raise ParameterError(f"{option} {path}: cannot write ({exc.strerror or exc})") from None


def _check_outputs(plot: str | None, histories: dict[str, Path]) -> None:
    """Refuse now, not after the run, a figure of a format matplotlib does not write and an output file whose
    folder cannot be written (the figure's, :func:`~rocking.plot.response.plot_responses` creates)."""
    for path in histories.values():
        _check_folder("--history", path)
    if plot is None:
        return
    from matplotlib.backend_bases import FigureCanvasBase

    formats = FigureCanvasBase.get_supported_filetypes()
    suffix = Path(plot).suffix
    # No suffix: matplotlib writes its default format (PNG) under the name given.
    if suffix and suffix[1:].lower() not in formats:
        raise ParameterError(f"--plot must end in one of {', '.join('.' + f for f in formats)} (got {plot!r})")
    _check_folder("--plot", Path(plot), created=True)


def _check_folder(option: str, path: Path, created: bool = False) -> None:
    """Refuse ``path`` if its folder cannot be written, or does not exist unless the writer creates it
    (``created``: then the first existing folder above it must be writable)."""
    folder = path.parent
    while created and not folder.exists() and folder != folder.parent:  # up to "/" or "." (a deleted cwd)
        folder = folder.parent
    with _writing(option, path):
        # A probe file: permissions, read-only mounts and pseudo file systems all answer the same way.
        with tempfile.TemporaryFile(dir=folder):
            pass


def _history_files(history: str | None, labels: list[str]) -> dict[str, Path]:
    """The file of each response's history: ``--history`` for the first, ``<stem>-<label><suffix>`` for the others."""
    if history is None:
        return {}
    path = Path(history)
    if path.suffix.lower() not in HISTORY_FORMATS:
        raise ParameterError(f"--history must end in {' or '.join(HISTORY_FORMATS)} (got {history!r})")
    others = {label: path.with_name(f"{path.stem}-{label.replace(' ', '_')}{path.suffix}") for label in labels[1:]}
    return {labels[0]: path, **others}


def _tuning_text() -> str:
    """``omega_ratio 1, zeta 0.05, h 0.05 m``: the studies' defaults of a damper relative to the block, read from
    :class:`rocking.Tuning`."""
    units = {"h": " m"}
    return ", ".join(f"{n} {python_default(Tuning, n):g}{units.get(n, '')}" for n in TUNING_DEFAULTS)


def _add_simulate_damper(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group(
        "damper (none given: the bare block)",
        "In SI as rocking.Damper(m, k_m, c, h), or relative to the block as "
        "rocking.Damper.from_nondim(block, gamma, T_m or omega_ratio, zeta, h) with the studies' defaults "
        f"(rocking.Tuning: {_tuning_text()}), so that --gamma alone is the damper a study runs.",
    )
    g.add_argument("--m", type=float, help="mass, kg (with --k-m)")
    g.add_argument("--k-m", type=float, help="spring stiffness, N/m")
    g.add_argument("--c", type=float, help=f"dashpot coefficient, N s/m ({default_text(Damper, 'c')})")
    g.add_argument(
        "--h",
        type=float,
        help=f"height of the guide above the top of the block, m ({default_text(Tuning, 'h', 'm')} with --gamma, "
        f"as rocking.Tuning; {default_text(Damper, 'h', 'm')} with --m, as rocking.Damper)",
    )
    g.add_argument("--gamma", type=float, help="mass ratio m/M: a damper relative to the block")
    tuning = g.add_mutually_exclusive_group()
    tuning.add_argument("--T-m", type=float, help="damper period, s")
    tuning.add_argument(
        "--omega-ratio",
        type=float,
        help=f"damper frequency over the block's, omega_m / p ({default_text(Tuning, 'omega_ratio')} "
        "without --T-m, as rocking.Tuning)",
    )
    g.add_argument("--zeta", type=float, help=f"damping ratio, with --gamma ({default_text(Tuning, 'zeta')})")
    g.add_argument("--no-damper", action="store_true", help="ignore the damper options: the bare block")
    g.add_argument("--model", help="model variant by name or generated folder (default: omd, or block without damper)")
    g.add_argument(
        "--param", action="append", metavar="NAME=VALUE", help="a parameter of the variant's bodies, SI (repeatable)"
    )
    g = p.add_argument_group(
        "end stops of the damper's guide (none given: the paper's unlimited guide)",
        "As rocking.Stops.at_edges(block, damper): 20 mm bumper pads at the block's edges, on the model omd_stops; "
        "--L, --k-b, --c-b replace its values (and imply --stops), as rocking.Stops(L, k_b, c_b).",
    )
    g.add_argument("--stops", action="store_true", help="bumper pads at the block's edges (Stops.at_edges)")
    g.add_argument(
        "--L",
        type=float,
        help=f"half-stroke from the centre to either bumper, m, at most B/2 (default B/2 - {BUMPER_DEPTH:g})",
    )
    g.add_argument(
        "--k-b",
        type=float,
        help=f"bumper stiffness, N/m (default {BUMPER_STIFFNESS:g}: a neoprene pad 20 mm thick of 50 x 50 mm, "
        "E A / t with E = 5 MPa)",
    )
    g.add_argument(
        "--c-b", type=float, help=f"bumper dashpot, N s/m (default: a damping ratio of {BUMPER_DAMPING_RATIO:g})"
    )
    g.add_argument(
        "--bumper-law",
        choices=tuple(BUMPER_LAWS),
        help="the pads' contact law (default kelvin-voigt: max(0, k_b delta + c_b ddelta); hunt-crossley: "
        "max(0, k_b delta^n (1 + chi(e_b) ddelta / v_in)), on the model omd_stops_hc)",
    )
    g.add_argument("--n-b", type=float, help="Hunt-Crossley exponent n, in [1, 10] (default 1.5, Hertzian contact)")
    g.add_argument(
        "--e-b",
        type=float,
        help=f"Hunt-Crossley restitution of one impact on a pad, {RANGES['e_b'].text()} "
        f"(default {BUMPER_RESTITUTION:.4f}, the Kelvin-Voigt pad's; with --n-b, "
        "implies --bumper-law hunt-crossley; its default --k-b gives the Kelvin-Voigt pad's force at full depth)",
    )


def _add_simulate(sub) -> None:
    p = add_parser(
        sub,
        "simulate",
        "response of a block, with or without a damper, to a pulse",
        "Response of a block, with or without a damper, to a pulse (one-sine by default), as rocking.simulate. "
        + block_help(),
    )
    add_block_options(p)
    _add_simulate_damper(p)
    g = p.add_argument_group(
        "pulse",
        "As rocking.OneSinePulse.from_nondim(block, beta, Omega, psi, sign) or, in SI, "
        "rocking.OneSinePulse(a_g, omega_g, psi, sign); --pulse picks another family (docs/model.md section 12) "
        "with the same options: OneCosinePulse, RickerWavelet (antisymmetric with ricker-anti), "
        "MavroeidisPapageorgiou(a_g, omega_g, gamma_mp, nu, sign). omega_g is 2 pi over the period of the cycle "
        "(sine, cosine), of the Fourier peak (both Ricker wavelets, as Vassiliou and Makris 2011) or of the "
        "carrier (mp).",
    )
    g.add_argument("--pulse", choices=tuple(PULSES), help="family of the pulse (default sine)")
    g.add_argument("--beta", type=float, help="amplitude ratio a_g / (g tan alpha)")
    g.add_argument("--Omega", type=float, help="frequency ratio omega_g / p")
    g.add_argument("--a-g", type=float, help="amplitude, m/s2")
    g.add_argument("--omega-g", type=float, help="circular frequency, rad/s")
    g.add_argument("--psi", type=float, help=f"phase at t = 0, rad ({default_text(OneSinePulse, 'psi')})")
    g.add_argument("--gamma-mp", type=float, help="oscillations gamma of --pulse mp, > 1")
    g.add_argument("--nu", type=float, help="phase nu of --pulse mp, rad (default 0)")
    g.add_argument(
        "--sign",
        type=int,
        help=f"direction, +1 or -1: +1 pushes the ground right first ({default_text(OneSinePulse, 'sign')})",
    )
    g.add_argument(
        "--vertical-ratio",
        type=float,
        help="vertical component, rocking.Vertical(ratio, phase): ddy_g = ratio a_g f(t + phase / omega_g), > 0 "
        "up, the pulse's own shape and period, unsigned by --sign (docs/model.md section 14; default none)",
    )
    g.add_argument(
        "--vertical-phase", type=float, help="lead of the vertical shape, rad, in [0, 2 pi) (default 0, in phase)"
    )
    g = p.add_argument_group(
        "recorded motion (instead of a pulse)",
        "As rocking.SampledMotion(a, dt, scale, sign) from rocking.model.records.read_record(FILE, unit).",
    )
    g.add_argument("--motion", metavar="FILE", help="a record: PEER NGA .AT2 (in g), or columns 'time, a'")
    g.add_argument(
        "--unit",
        choices=tuple(UNITS),
        help="unit of the accelerations of a text or CSV --motion (default: the one its header states, "
        "'time [s], a [g]'; if both, they must agree)",
    )
    g.add_argument(
        "--vertical",
        metavar="FILE",
        help="the record's vertical component, > 0 up, in the same format and unit and at the same dt (0 after "
        "its end; cut at the horizontal record's): SampledMotion(a_v=...), docs/model.md section 14",
    )
    g.add_argument("--scale", type=float, help="factor on the record (default 1)")
    g.add_argument("--pga", type=float, help="scale the record to this peak ground acceleration, m/s2")
    add_floor_options(p)
    g = p.add_argument_group("run and output")
    g.add_argument("--backend", choices=NAMES, help=f"back end ({default_text(simulate, 'backend')})")
    g.add_argument(
        "--rtol", type=float, help=f"relative tolerance of the integrator ({default_text(simulate, 'rtol')})"
    )
    g.add_argument("--t-max", type=float, help="end time, s (default: 15 s after the pulse)")
    g.add_argument(
        "--check",
        choices=CHECKS,
        help="'tolerance': run again down a ladder of tolerances (rtol / 100, at most 1e-10, ... 1e-12) and flag "
        "a sensitive response (default for --motion; 'none' for a pulse)",
    )
    g.add_argument("--json", action="store_true", help="machine-readable result on stdout")
    g.add_argument(
        "--early-verdict",
        action="store_true",
        help="end the run once its verdict and maxima are final (status bounded, docs/simulation.md rule 4): "
        "theta_max, x_max and the verdict are those of the run followed to rest, impacts and t_end count to that "
        "instant (default: every run is followed to rest, with or without --plot and --history)",
    )
    g.add_argument(
        "--follow-to-rest",
        action="store_true",
        help="follow the response to rest: the default, kept so that older commands still run",
    )
    g.add_argument(
        "--plot",
        metavar="FILE",
        help="figure of theta/alpha, the base's slip u on a floor with friction (--mu), x and the ground acceleration",
    )
    g.add_argument("--compare", action="store_true", help="also run the block alone, on the same axes")
    g.add_argument(
        "--history",
        metavar="FILE",
        help="time history on a uniform grid with the loads, as Response.to_dataset: .csv "
        "(units in the column names) or .nc (NetCDF); with --compare the block alone's goes to FILE-block_alone",
    )
    g.add_argument(
        "--history-dt",
        type=float,
        metavar="SECONDS",
        help="spacing of --history and --plot, s (default: a hundredth of the shorter of the pulse's and the block's "
        "periods, at most a record's dt)",
    )
    p.set_defaults(func=_cmd_simulate)


# --- derive ---------------------------------------------------------------------------------------


def run_derive(argv: list[str]) -> int:
    """``python -m rocking.derive ARGV``: the derive package's own command line.

    Parameters
    ----------
    argv : list of str
        Its options (what follows ``rocking derive``).

    Returns
    -------
    int
        Its exit code; 1, with a one-line message naming the install command,
        when SymPy or another package of the optional ``derive`` extra is missing.
    """
    try:
        from ..derive.cli import main as derive_main

        return derive_main(argv, prog="rocking derive")
    except ModuleNotFoundError as exc:
        if (exc.name or "").partition(".")[0] not in DERIVE_EXTRA:
            raise
        print(
            f"rocking derive: error: {exc.name} is not installed; the derivation is an optional extra: "
            f"{DERIVE_INSTALL}",
            file=sys.stderr,
        )
        return 1


def _add_derive(sub) -> None:
    # No options of its own: everything after "derive" goes to the derive package (main() hands it over
    # before parsing); this parser only lists the command in rocking --help.
    p = add_parser(
        sub,
        "derive",
        "derive the models' equations and code from their specs (SymPy; rocking derive --help for its options)",
        f"The derive package's command line (python -m rocking.derive); needs SymPy: {DERIVE_INSTALL}.",
        add_help=False,
    )
    p.add_argument("argv", nargs=argparse.REMAINDER, help="options of the derivation")


# --- the command ----------------------------------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    """The ``rocking`` parser with every subcommand."""
    parser = argparse.ArgumentParser(prog="rocking", description=DESCRIPTION, allow_abbrev=False)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_simulate(sub)
    add_study_commands(sub)
    _add_verify(sub)
    _add_derive(sub)
    return parser


def _subcommand(parser: argparse.ArgumentParser, command: str) -> argparse.ArgumentParser:
    """The parser of ``command``."""
    (commands,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return commands.choices[command]


def refuse_unknown(parser: argparse.ArgumentParser, command: str, unknown: list[str]) -> None:
    """Exit (2) with the usage of ``command``, not the top level's, naming the closest option to each typo.

    argparse reports an unknown option of a subcommand through the top-level parser, whose usage lists
    the commands, not the options a user mistyped (``--gama`` for ``--gamma``).
    """
    sub = _subcommand(parser, command)
    options = [s for action in sub._actions for s in action.option_strings]
    words = []
    for token in unknown:
        close = difflib.get_close_matches(token.partition("=")[0], options, n=1) if token.startswith("-") else []
        words.append(f"{token} (did you mean {close[0]}?)" if close else token)
    sub.error(f"unrecognized arguments: {', '.join(words)}")


def main(argv: list[str] | None = None) -> int:
    """Run ``rocking ARGV``.

    Parameters
    ----------
    argv : list of str, optional
        The arguments; default ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit code: 0 on success, 2 for bad parameters, 1 for a run or a C build that
        failed (one line on stderr in both cases), 1 without a word when the reader of
        stdout went away (``rocking simulate --json | head``).
    """
    try:
        code = _run(argv, own_process=argv is None)
        # Flushed here, so that a reader gone away is seen now and not as an exception at exit.
        sys.stdout.flush()
        return code
    except BrokenPipeError:
        # The Python docs' "Note on SIGPIPE": Python's exit flushes stdout again, so point it at devnull first.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


def hide_dask(args: argparse.Namespace) -> None:
    """Make Dask unimportable in this process unless ``args`` ask for a Dask scheduler (:data:`DASK_OPTIONS`).

    xarray imports ``dask.array`` at its first Dataset when Dask is installed (0.5 s of CPU, as much as a small
    study's computation), only to tell Dask arrays apart, which rocking never gives it: Dask runs the tiles of
    ``--scheduler`` and ``--dask-workers`` only. A module set to None in :data:`sys.modules` raises
    ModuleNotFoundError when imported (the import system's rule), which xarray takes for Dask not installed.
    Only in a process that is the command's own (:func:`main` without arguments): not in a caller's, whose
    xarray may hold Dask arrays.
    """
    if not any(getattr(args, name, None) is not None for name in DASK_OPTIONS):
        sys.modules.setdefault("dask", None)  # type: ignore[arg-type]


def _run(argv: list[str] | None, own_process: bool = False) -> int:
    """:func:`main` but for a closed stdout; ``own_process``: the process is the command's (:func:`hide_dask`)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["derive"]:
        # argparse cannot pass options it does not know through a subparser (its REMAINDER
        # skips a leading --option): hand them over before parsing.
        return run_derive(argv[1:])
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)
    if unknown:
        refuse_unknown(parser, args.command, unknown)
    try:
        if getattr(args, "config", None):
            args = apply_config(parser, args, argv)
        if own_process:
            hide_dask(args)
            claim_process()
        return args.func(args)
    except (ParameterError, ModelError) as exc:
        flags = flags_of(_subcommand(parser, args.command))
        print(f"rocking {args.command}: error: {named_as_flag(flags, str(exc))}", file=sys.stderr)
        return 2
    except (SimulationError, CBuildError) as exc:  # valid input, but the run or the build failed: no traceback
        print(f"rocking {args.command}: error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
