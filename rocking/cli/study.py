"""The study subcommands of the ``rocking`` command: ``map``, ``spectrum``, ``optimize``, ``demo``, ``redraw``.

:func:`add_study_commands` adds them to the ``rocking`` parser's subparsers;
each sets ``func(args) -> exit code``. A study writes ``<out>/<kind>.nc``,
``.csv``, ``.json``, ``.png`` and ``.pdf``, and keeps its finished tiles in
``<out>/runs`` so that an interrupted run resumes where it stopped.

Each command calls the Python study API with the options given and nothing
else (:mod:`.options`): ``rocking map ...`` computes what
``rocking.overturning_map(Setting(block, ...), Tuning(...), Grid(...), Grid(...))``
computes, with the same defaults. The grids (and the mass ratios of
``optimize``) have no default in Python; the command line's are below.

Bad parameters end with a one-line message naming the parameter and its valid
range and exit code 2 (argparse's own errors, e.g. an unknown option, too).
"""

from __future__ import annotations

import argparse
import re
import sys
import time
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..model.params import ParameterError
from ..model.plausibility import PlausibilityWarning
from ..model.records import UNITS
from ..model.stochastic import DEFAULT_SITE
from ..plot.figures import draw, draw_vertical_spectra, redraw
from ..sim.accuracy import CHECKS
from ..study.api import with_omega_ratio
from ..study.config import BACKENDS, PULSES, Grid, Setting, Tuning, Variant
from ..study.design import TM_GRID as DESIGN_TM_GRID
from ..study.design import ZETA_GRID, design
from ..study.directions import DIRECTIONS
from ..study.files import DiskFull, make_folder, no_space
from ..study.fragility import FITTED, FitWarning
from ..study.ida import LEVELS, incremental_dynamic_analysis
from ..study.optimize import TM_GRID, USELESS_GAIN, optimal_damper
from ..study.overturning_map import UndeterminedWarning, overturning_map
from ..study.result import Study
from ..study.spectrum import envelope as spectrum_envelope
from ..study.spectrum import minimum_overturning_spectrum
from ..study.storage import save
from ..study.suite import Suite, split_unit, suite_of
from ..study.threshold import LAM_GRID, OMEGA_GRID, P_GRID, threshold_map, thresholds
from ..study.threshold import TM_GRID as THRESHOLD_TM_GRID
from ..study.tiles import Execution, Interrupted, TileWarning
from ..study.vocabulary import BELOW, BRACKETED, FIT_STATUSES
from .options import (
    add_block_options,
    add_parser,
    block_from,
    block_help,
    default_text,
    flag,
    flags,
    given,
    params_from,
    python_default,
)
from .rerun import CURRENT, check_same, command_record

#: Default grids (MIN, MAX, N) of the commands; docs/model.md section 9 gives the ranges. The beta
#: scans of spectra start at 0.5, below the uplift threshold (about 0.9 .. 1.1 for the reference
#: block), so that beta_min is bracketed also for long, quasi-static pulses.
MAP_OMEGA, MAP_BETA = (0.5, 15.0, 146), (1.0, 15.0, 141)
SPECTRUM_OMEGA, SPECTRUM_BETA = (0.5, 15.0, 59), (0.5, 15.0, 117)
OPTIMIZE_OMEGA, OPTIMIZE_BETA = (0.5, 15.0, 30), (0.5, 15.0, 59)
OPTIMIZE_GAMMAS = (0.02, 0.05, 0.1)
#: The demo's spectra under a vertical component: its ratios and modest grids (about 20 s on 2 cores).
VERTICAL_RATIOS = (0.0, 0.5, 1.0)
VERTICAL_OMEGA, VERTICAL_BETA = (0.5, 15.0, 30), (0.5, 15.0, 59)
#: The band of pulses of ``design`` and its beta scan (reaching above the damped block's beta_min at Omega = 8).
DESIGN_OMEGA, DESIGN_BETA = (2.0, 8.0, 7), (0.5, 25.0, 50)

#: Default levels of ida (scale factors) and fragility (PGA, m/s^2).
IDA_SCALES, FRAGILITY_LEVELS = (0.25, 4.0, 16), (0.5, 10.0, 20)
#: Options of the stochastic site model (rocking.model.stochastic.SiteModel).
SITE_OPTIONS = ("arias", "d595", "t_mid", "f_mid", "f_slope", "zeta_f", "f_c", "dt", "duration")

#: The options of a suite of pulses besides ``--pulses``.
PULSE_SUITE_OPTIONS = ("periods", "amplitude", "gamma_mp", "nu")

#: Options that set the omd damper (a Tuning), refused with a model variant.
DAMPER_OPTIONS = ("gamma", "Tm_ratio", "omega_ratio", "zeta", "h", "stops")


# --- options -------------------------------------------------------------------------


def _add_solver(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group(
        "solver and execution",
        "As rocking.Setting(block, rtol, t_after, backend) and "
        "rocking.Execution(workers, scheduler, dask_workers, progress).",
    )
    g.add_argument(
        "--rtol",
        type=float,
        help=f"relative tolerance of the integrator, in [1e-12, 0.01] ({default_text(Setting, 'rtol')})",
    )
    g.add_argument(
        "--t-after", type=float, help=f"time followed after the pulse, s ({default_text(Setting, 't_after')})"
    )
    g.add_argument("--backend", help=f"{' or '.join(BACKENDS)} ({default_text(Setting, 'backend')})")
    g.add_argument(
        "--workers", type=int, help="local workers (default: all cores): threads on the C back end, processes on NumPy"
    )
    g.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask cluster at ADDRESS (tcp://host:port)")
    g.add_argument("--dask-workers", type=int, metavar="N", help="run on a local Dask cluster of N worker processes")
    g.add_argument("--out", default="out", help="output folder (default out); finished tiles are kept in OUT/runs")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    g.add_argument(
        "--config",
        metavar="SAVED.json",
        help="rerun the study saved in SAVED.json with its options (those given here win: --out, --workers, ...)",
    )


def _add_check(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--check",
        choices=CHECKS,
        help="'tolerance': run every response again at rtol / 100 and flag the sensitive ones, as rocking simulate "
        "--check (default for records and --stochastic; 'none' for --pulses)",
    )


def _add_damper(p: argparse.ArgumentParser, *, tuned: bool, searched: bool, stops: bool = True) -> None:
    """Damper options: one damper (``tuned``: a Tuning) and/or the mass ratios of the optimisation (``searched``)."""
    # The defaults shown are those of the Python call each command makes: Tuning, or optimal_damper.
    source = Tuning if tuned else optimal_damper
    g = p.add_argument_group(
        "damper", "As rocking.Tuning(gamma, omega_ratio, zeta, h, stops)." if tuned else "As rocking.optimal_damper."
    )
    if stops:
        g.add_argument(
            "--stops",
            action="store_const",
            const=True,
            help="the guide ends in the stops of rocking.Stops.at_edges (default: the paper's unlimited guide)",
        )
    if tuned:
        g.add_argument("--gamma", type=float, help=f"mass ratio m/M ({default_text(Tuning, 'gamma')})")
        tuning = g.add_mutually_exclusive_group()
        tuning.add_argument(
            "--Tm-ratio",
            type=float,
            help=f"damper period T_m p / (2 pi), i.e. 1 / omega_ratio ({default_text(Tuning, 'omega_ratio')})",
        )
        tuning.add_argument(
            "--omega-ratio",
            type=float,
            help=f"damper frequency omega_m / p ({default_text(Tuning, 'omega_ratio')})",
        )
    if searched:
        g.add_argument(
            "--gammas",
            type=float,
            nargs="+",
            default=list(OPTIMIZE_GAMMAS),
            help=f"mass ratios of the optimal damper (default {' '.join(map(str, OPTIMIZE_GAMMAS))}); "
            "the best over them is reported too",
        )
    g.add_argument("--zeta", type=float, help=f"damping ratio ({default_text(source, 'zeta')})")
    g.add_argument(
        "--h", type=float, help=f"height of the guide above the top of the block, m ({default_text(source, 'h')})"
    )


def _add_variant(p: argparse.ArgumentParser) -> None:
    """``--model`` and ``--param``: any generated model with its own parameters, instead of the omd damper."""
    g = p.add_argument_group("model variant (instead of the damper options)", "As rocking.Variant(model, params).")
    g.add_argument(
        "--model",
        metavar="NAME|FOLDER",
        help="generated model by name (omd, pendulum, omd2, ...) or folder written by python -m rocking.derive "
        "(default omd, tuned by the damper options)",
    )
    g.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a parameter of the model's own, SI units (repeat for each); with --model other than omd, "
        "every parameter not set by the block is needed",
    )


def _add_grid(p: argparse.ArgumentParser, name: str, default: tuple, text: str) -> None:
    p.add_argument(
        f"--{name}",
        nargs=3,
        metavar=("MIN", "MAX", "N"),
        default=default,
        help=f"{text} (default {default[0]:g} {default[1]:g} {default[2]})",
    )


def _add_levels(p: argparse.ArgumentParser, name: str, default: tuple, text: str) -> None:
    """``--NAME MIN MAX N`` (evenly spaced, ``default``) or ``--NAME-log MIN MAX N`` (evenly spaced logarithms)."""
    g = p.add_mutually_exclusive_group()
    _add_grid(g, name, default, f"{text}, evenly spaced")
    g.add_argument(
        f"--{name}-log",
        nargs=3,
        metavar=("MIN", "MAX", "N"),
        help=f"{text}, evenly spaced in logarithm (MIN > 0), as rocking.Grid(..., log=True)",
    )


def _add_pulse(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("pulse family", "As rocking.Setting(block, pulse=..., gamma_mp=..., nu=...).")
    g.add_argument(
        "--pulse",
        choices=[f.replace("_", "-") for f in PULSES],
        help="family of every pulse, docs/model.md section 12 (default sine); Omega = omega_g / p, "
        "omega_g 2 pi over the period of the cycle, of the Fourier peak (ricker, ricker-anti) or of "
        "the carrier (mp)",
    )
    g.add_argument("--gamma-mp", type=float, help="oscillations gamma of --pulse mp, > 1")
    g.add_argument("--nu", type=float, help="phase nu of --pulse mp, rad (default 0)")


def _add_vertical(p: argparse.ArgumentParser) -> None:
    """``--vertical-ratio`` and ``--vertical-phase`` of the maps and spectra: every pulse's vertical component."""
    g = p.add_argument_group(
        "vertical component",
        "As rocking.Setting(block, vertical_ratio=..., vertical_phase=...): every pulse with "
        "rocking.Vertical(ratio, phase), ddy_g > 0 up, unsigned by the direction (docs/model.md section 14).",
    )
    g.add_argument(
        "--vertical-ratio",
        type=float,
        metavar="R",
        help="vertical amplitude over the horizontal a_g, in [0, 10]: ddy_g = R a_g f(t + PHI / omega_g) on the "
        "pulse; where g + ddy_g reaches 0 a run ends with status flight, no verdict "
        f"({default_text(Setting, 'vertical_ratio')})",
    )
    g.add_argument(
        "--vertical-phase",
        type=float,
        metavar="PHI",
        help=f"lead PHI of the vertical shape, rad, in [0, 2 pi) ({default_text(Setting, 'vertical_phase')})",
    )


def _add_directions(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--directions",
        choices=DIRECTIONS,
        help="signs of the pulses: auto runs both unless the block (e = 0) and its damper are symmetric, "
        f"and reports the envelope ({default_text(overturning_map, 'directions')})",
    )


def _add_search(p, default: tuple, function) -> None:
    """``--Tm-ratio MIN MAX N`` (the coarse log grid of ``T_m p / (2 pi)``, ``default``) and ``--refine`` of a
    study that searches the damper period; ``function``: the Python call whose default ``refine`` is shown."""
    p.add_argument(
        "--Tm-ratio",
        nargs=3,
        metavar=("MIN", "MAX", "N"),
        help=f"coarse log grid of damper periods T_m p / (2 pi) (default {default[0]:g} {default[1]:g} {default[2]})",
    )
    p.add_argument(
        "--refine",
        type=int,
        help=f"refinement points each side of the best coarse point ({default_text(function, 'refine')})",
    )


def _add_tol(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--beta-tol",
        type=float,
        help=f"relative tolerance of the bisection on beta ({default_text(minimum_overturning_spectrum, 'tol')})",
    )


# --- building the study's objects from the options -----------------------------------------


def grid_from(name: str, values, *, log: bool = False) -> Grid:
    """A :class:`Grid` from the three strings ``MIN MAX N`` of an option."""
    try:
        low, high, n = float(values[0]), float(values[1]), int(values[2])
    except (TypeError, ValueError):
        raise ParameterError(
            f"--{name} takes MIN MAX N: two numbers and an integer (got {' '.join(map(str, values))})"
        ) from None
    return Grid(name, low, high, n, log=log)


def setting_from(args) -> Setting:
    """The study's :class:`Setting` from the options given (``--pulse ricker-anti`` is ``pulse="ricker_anti"``)."""
    # ida and fragility have no --pulse: their --gamma-mp and --nu shape the pulses of their suite.
    pulse = given(args, ("pulse", "gamma_mp", "nu")) if "pulse" in vars(args) else {}
    # map and spectrum: their pulses' vertical component (ida's and fragility's --vertical-ratio is their suite's).
    if "pulse" in vars(args):
        pulse.update(given(args, ("vertical_ratio", "vertical_phase")))
    if "pulse" in pulse:
        pulse["pulse"] = pulse["pulse"].replace("-", "_")
    return Setting(block_from(args), **given(args, ("rtol", "t_after", "backend")), **pulse)


def tuning_from(args) -> Tuning:
    """The omd damper of the options, as ``rocking.Tuning`` with the options given (``--Tm-ratio``: 1 / omega_ratio)."""
    try:
        return Tuning(**with_omega_ratio(given(args, ("gamma", "Tm_ratio", "omega_ratio", "zeta", "h", "stops"))))
    except ParameterError as exc:
        raise ParameterError(str(exc).replace("Tm_ratio", "--Tm-ratio")) from None


def damper_from(args) -> Tuning | Variant:
    """The damper of ``map``/``spectrum``: the omd :class:`Tuning`, or a :class:`Variant` with ``--model``/``--param``.

    ``--model omd`` without ``--param`` is the tuned omd damper; any other
    ``--model``, or ``--param`` given, is a variant whose parameters are the
    ``--param`` values, and the damper options are then refused.
    """
    model, items = getattr(args, "model", None), getattr(args, "param", [])
    if model is None and not items:
        return tuning_from(args)
    if model is None:
        raise ParameterError("--param sets a model's parameters: give the model with --model NAME|FOLDER")
    if model == "omd" and not items:
        return tuning_from(args)
    options = given(args, DAMPER_OPTIONS)
    if options:
        raise ParameterError(
            f"{flags(options)}: damper options of the omd model; with --model {model} "
            "give the model's own parameters as --param NAME=VALUE"
        )
    return Variant(model, params_from(items))


def out_from(args) -> Path:
    """The output folder ``--out``, created if needed: refused now if it cannot be written, not after the study."""
    return make_folder(args.out, "--out")


def execution_from(args) -> Execution:
    progress = {"progress": False} if args.no_progress else {}
    return Execution(**given(args, ("workers", "scheduler", "dask_workers")), **progress)


def _tol(args) -> dict:
    """``tol=`` of the spectrum and optimize calls, only when ``--beta-tol`` is given."""
    return {"tol": args.beta_tol} if args.beta_tol is not None else {}


# --- commands --------------------------------------------------------------------------


def _report(study: Study, out: Path, name: str | None = None) -> list[Path]:
    """Save the study's data and figure as ``name`` (default: its kind); print where they are and how it ran."""
    current = CURRENT.get() or {}
    run = study.run
    kept = run["tiles_computed"] + run["tiles_reused"]
    try:
        paths = save(study, out, name, command=current.get("command"))
    except DiskFull as exc:
        raise DiskFull(exc.path, kept=kept) from None
    try:
        paths += draw(study, out, name)
    except Exception:
        # matplotlib's writers fail on a full disk in their own ways (an OSError, or an AttributeError of the PDF
        # stream): the free space tells. The data are published; the figures are redrawn by a rerun or redraw.
        if not no_space(out):
            raise
        raise DiskFull(out / f"{name or study.kind}.png and .pdf", kept=kept) from None
    print(
        f"{study.kind}: {run['tiles_computed']} tiles computed, {run['tiles_reused']} reused, "
        f"{run['wall_s']:.1f} s; wrote {', '.join(str(p) for p in paths)}"
    )
    chosen = study.config["directions"]
    signs = " and ".join(f"{s:+d}" for s in chosen["signs"])
    print(f"{study.kind}: pulses of sign {signs}: {chosen['reason']}")
    if current.get("rerun"):
        print(check_same(study, *current["rerun"]))
    return paths


def _inputs(args) -> tuple[tuple, Path]:
    """``(setting, damper, Omega, beta, execution)`` of ``map``/``spectrum``, then the output folder.

    In this order: bad parameters are refused before the folder is created.
    """
    inputs = (
        setting_from(args),
        damper_from(args),
        grid_from("Omega", args.Omega),
        grid_from("beta", args.beta),
        execution_from(args),
    )
    return inputs, out_from(args)


def _refinement(args) -> dict:
    """``full=``, ``coarse=`` and ``verify=`` of a map, as given; --full refused with the others."""
    if args.full and (args.coarse is not None or args.verify is not None):
        raise ParameterError(
            "give --coarse/--verify (the steps of the adaptive refinement) or --full (every cell), not both"
        )
    return given(args, ("full", "coarse", "verify"))


def _cmd_map(args) -> int:
    tile = {"tile": tuple(args.tile)} if args.tile is not None else {}
    refinement = _refinement(args)
    inputs, out = _inputs(args)
    study = overturning_map(*inputs, runs=out / "runs", **tile, **given(args, ("directions",)), **refinement)
    _report(study, out)
    _print_map(study)
    return 0


def _print_map(study: Study) -> None:
    s = study.summary
    print(
        f"map: {s['cells']} cells; overturned {s['bare_overturned']} alone, {s['damper_overturned']} with the damper; "
        f"saved {s['saved']} ({s['saved_past_edges']} only with the mass past the block's edge), lost {s['lost']}"
        + (f"; {unknown} without a verdict" if (unknown := s["bare_undetermined"] + s["damper_undetermined"]) else "")
    )
    refinement, run = study.config["refinement"], study.run
    if refinement["adaptive"]:
        print(
            f"map: adaptive (coarse step {refinement['coarse']}, verified from step {refinement['verify']}): "
            f"{run['responses']} of {run['responses_full_grid']} responses computed in {run['rounds']} rounds; "
            f"cells not computed take the outcome around them (--full computes every cell)\n"
            f"map: {study.summary['guarantee']}"
        )


def _cmd_spectrum(args) -> int:
    inputs, out = _inputs(args)
    study = minimum_overturning_spectrum(
        *inputs, runs=out / "runs", **_tol(args), **given(args, ("directions",)), **given(args, ("coarse",))
    )
    _report(study, out)
    _print_spectrum(study)
    return 0


def _print_spectrum(study: Study) -> None:
    for part in ("bare", "damper"):
        s = study.summary[part]
        print(
            f"spectrum, {part}: beta_min bracketed at {s['bracketed']} frequencies, "
            f"not reached in the scan at {s['not_overturned_in_scan']}; {s['windows']} safe windows above beta_min"
        )
    env = spectrum_envelope(study.data)
    flag, beta_min = ({part: env[k].sel(part=part).values for part in ("bare", "damper")} for k in ("flag", "beta_min"))
    both = (flag["bare"] == BRACKETED) & (flag["damper"] != BELOW)
    if both.any():
        gain = beta_min["damper"][both] / beta_min["bare"][both]
        print(
            f"spectrum: gain of the damper (the ratio of the envelopes) from {gain.min():.3g} to {gain.max():.3g} "
            f"over {int(both.sum())} frequencies; below 1 at {int((gain < 1).sum())}"
        )
    refinement, run = study.config["refinement"], study.run
    if refinement["adaptive"]:
        print(
            f"spectrum: adaptive scans (coarse step {refinement['coarse']}): {run['scan_responses']} of "
            f"{run['scan_responses_full']} scan responses computed ({run['responses']} with the bisections); "
            "amplitudes not computed take the outcome around them (without --coarse every amplitude is computed)"
        )


def _optimize(args, setting: Setting, execution: Execution, Omega: Grid, beta: Grid, **search) -> Study:
    """``optimal_damper`` with the options given (zeta, h, tolerance) and ``search`` (Tm, refine) if any."""
    return optimal_damper(
        setting,
        args.gammas,
        Omega,
        beta,
        execution,
        runs=Path(args.out) / "runs",
        **given(args, ("zeta", "h", "stops", "directions")),
        **_tol(args),
        **search,
    )


def _print_threshold(study: Study) -> None:
    Omega_max = float(study.data["Omega"].values[-1])
    for key, t in study.summary["Omega_star"].items():
        who = "best over gamma" if key == "best" else f"gamma = {key}"
        if t["status"] == "bracketed":
            print(f"Omega* ({who}) = {t['Omega_star']:.3g}, between the scanned {t['low']:.3g} and {t['high']:.3g}")
        elif t["status"] == "above_range":
            print(f"Omega* ({who}) > {t['low']:.3g}: the damper still helps at the highest frequency with a gain")
        elif t["status"] == "below_range":
            print(f"Omega* ({who}) <= {t['high']:.3g}: the damper does not help at any frequency scanned")
        else:
            print(f"Omega* ({who}) unknown: no gain is defined (the bare block's beta_min is outside the beta scan)")
        if t["defined_up_to"] is not None and t["defined_up_to"] < Omega_max:
            print(
                f"  (gain undefined above Omega = {t['defined_up_to']:.3g}: the bare block does not overturn "
                "within the beta scan there; widen --beta to see further)"
            )


def _cmd_optimize(args) -> int:
    search = given(args, ("refine",))
    if args.Tm_ratio is not None:
        search["Tm"] = grid_from("Tm-ratio", args.Tm_ratio, log=True)
    setting, execution = setting_from(args), execution_from(args)
    Omega, beta = grid_from("Omega", args.Omega), grid_from("beta", args.beta)
    out = out_from(args)
    study = _optimize(args, setting, execution, Omega, beta, **search)
    _report(study, out)
    _print_threshold(study)
    return 0


def _cmd_design(args) -> int:
    setting, execution = setting_from(args), execution_from(args)
    Omega, beta = grid_from("Omega", args.Omega), grid_from("beta", args.beta)
    search = {}
    if args.Tm_ratio is not None:
        search["Tm"] = grid_from("Tm-ratio", args.Tm_ratio, log=True)
    if args.zeta_grid is not None:
        search["zeta"] = grid_from("zeta", args.zeta_grid, log=True)
    out = out_from(args)
    study = design(
        setting,
        Omega,
        beta,
        execution,
        runs=out / "runs",
        **given(args, ("gamma", "stroke", "h", "refine", "directions")),
        **_tol(args),
        **search,
    )
    _report(study, out)
    _print_design(study)
    return 0


def _print_design(study: Study) -> None:
    s, d = study.summary, study.summary["damper"]
    print(
        f"design: m = {d['m_kg']:.4g} kg (gamma = {d['gamma']:g}), k_m = {d['k_m_N_per_m']:.4g} N/m, "
        f"c = {d['c_N_s_per_m']:.4g} N s/m (T_m = {d['T_m_s']:.4g} s, T_m p / 2 pi = {d['Tm_ratio']:.3g}, "
        f"zeta = {d['zeta']:.3g}); stops at L = {d['L_m']:.3g} m, k_b = {d['k_b_N_per_m']:.4g} N/m, "
        f"c_b = {d['c_b_N_s_per_m']:.4g} N s/m"
    )
    print(f"design: {design_verdict(s)}")
    for warning in edge_warnings(s, d):
        print(f"design: warning: {warning}")
    print(
        f"design: stroke used at the pulses that overturn the block alone: up to {s['stroke_use_max']:.3g} L, "
        f"{s['stop_contacts_max']} stop contacts; {s['candidates_on_block']} of {s['candidates']} dampers tried "
        "keep their mass on the block"
    )
    if s["gain_undefined_at"]:
        print(
            f"design: gain undefined at Omega = {s['gain_undefined_at']} (the block alone does not overturn "
            "within the beta scan there; widen --beta)"
        )


def design_verdict(summary: dict) -> str:
    """What the design achieved, in words: it helps, gains nothing useful (worst gain <= USELESS_GAIN), makes some
    pulse worse, or has no verdict (the gain is undefined over the whole band)."""
    worst = summary["worst_gain"]
    if worst is None:
        return (
            "no verdict: the gain is undefined over the whole band (the block alone survives the beta scan; "
            "widen --beta)"
        )
    where = f"at Omega = {summary['worst_at_Omega']:.3g}"
    bound = ", a lower bound: the damped block survived the scan there" if summary["worst_gain_is_lower_bound"] else ""
    if worst > USELESS_GAIN:
        return f"helps: worst gain {worst:.2f} over the band ({where}{bound})"
    if worst >= 1.0:
        return f"no useful gain (worst gain {worst:.2f} <= {USELESS_GAIN:g}, {where}{bound})"
    return (
        f"makes some pulses worse: worst gain {worst:.2f} < 1 ({where}{bound}); no damper of this budget and "
        "stroke helps over the whole band"
    )


def edge_warnings(summary: dict, damper: dict) -> list[str]:
    """One warning per optimal parameter at an end of its search range, with the option that widens it."""
    out = []
    for name, value, edge, option in (
        ("T_m p / 2 pi", damper["Tm_ratio"], summary["Tm_at_edge"], "--Tm-ratio"),
        ("zeta", damper["zeta"], summary["zeta_at_edge"], "--zeta-grid"),
    ):
        if edge:
            end, bound = ("smallest", "MIN below") if edge < 0 else ("largest", "MAX above")
            out.append(
                f"the optimal {name} = {value:.3g} is the {end} of its search range: the best may lie "
                f"beyond; widen it with {option} MIN MAX N, {bound} {value:.3g}"
            )
    return out


def _cmd_threshold(args) -> int:
    grids = [grid_from(name, getattr(args, name)) for name in ("lam", "p", "Omega")]
    search = {"Tm": grid_from("Tm-ratio", args.Tm_ratio, log=True)} if args.Tm_ratio is not None else {}
    options = given(
        args, ("e_ratio", "gamma", "zeta", "h", "refine", "a_max", "rtol", "t_after", "backend", "directions")
    )
    execution, out = execution_from(args), out_from(args)
    study = threshold_map(*grids, execution, runs=out / "runs", **options, **_tol(args), **search)
    _report(study, out)
    _print_threshold_map(study)
    return 0


def _print_threshold_map(study: Study) -> None:
    found, bound = thresholds(study.data), study.summary["a_max_g"]
    lams, ps = found["lam"].values, found["p"].values
    for kind in ("unlimited", "stops"):
        print(
            f"threshold, {kind} guide: Omega* bracketed at {study.summary[kind]['bracketed']} of "
            f"{lams.size * ps.size} geometries"
        )
        status, star, low, high = (
            found[k].sel(part=kind).values for k in ("status", "Omega_star", "Omega_star_low", "Omega_star_high")
        )
        for i, lam in enumerate(lams):
            cells = []
            for j, p in enumerate(ps):
                text = {0: f"{star[i, j]:.3g}", 1: f"<= {high[i, j]:.3g}", 2: f"> {low[i, j]:.3g}"}
                cells.append(f"p = {p:g}: Omega* {text.get(int(status[i, j]), 'undefined')}")
            print(f"  lambda = {lam:g}: " + "; ".join(cells))
    for i, lam in enumerate(lams):
        safe = ", ".join(f"{x:.3g}" if np.isfinite(x) else "-" for x in found["safe_from"].values[i])
        print(
            f"threshold: lambda = {lam:g}: the block alone survives every pulse up to {bound:g} g from Omega = "
            f"{safe} (p = {', '.join(f'{p:g}' for p in ps)} rad/s)"
        )


def _suite_from(args) -> Suite:
    """The motions of ``ida``/``fragility``: ``--motions FILE[:UNIT]...``, ``--stochastic N --seed S`` (site
    options) or ``--pulses FAMILY --periods T...``, as :func:`rocking.study.suite.suite_of` makes them."""
    site = given(args, SITE_OPTIONS)
    motions = None if args.motions is None else [split_unit(m) for m in args.motions]
    try:
        return suite_of(
            motions,
            **given(args, ("unit", "stochastic", "seed", "vertical_ratio", "pulses", *PULSE_SUITE_OPTIONS)),
            site=site or None,
            g=block_from(args).g,
        )
    except ParameterError as exc:
        raise ParameterError(_as_flags(str(exc))) from None


def _as_flags(message: str) -> str:
    """A message of :func:`suite_of` naming the Python keywords of the options, with the command line's flags."""
    message = re.sub(r"\bsite\b(?!\.)", "site options (" + flags(SITE_OPTIONS[:2]) + ", ...)", message)
    for word in ("motions", "unit", "stochastic", "seed", "vertical_ratio", "pulses", *PULSE_SUITE_OPTIONS):
        message = re.sub(rf"\b{word}\b(?!\.)", flag(word), message)
    return message


def _cmd_ida(args) -> int:
    measure = "scale" if args.command == "ida" else args.im
    name = "scales" if measure == "scale" else "levels"
    log = getattr(args, f"{name}_log")
    grid = grid_from(name, getattr(args, name)) if log is None else grid_from(f"{name}-log", log, log=True)
    setting, damper, execution = setting_from(args), damper_from(args), execution_from(args)
    suite = _suite_from(args)
    out = out_from(args)
    study = incremental_dynamic_analysis(
        setting,
        damper,
        suite,
        grid,
        execution,
        measure_name=measure,
        runs=out / "runs",
        **given(args, ("directions", "check")),
    )
    _report(study, out)
    for line in fit_lines(study):
        print(line)
    return 0


def fit_lines(study: Study) -> list[str]:
    """What an IDA or a fragility says of each part, one line each: the fitted lognormal (its status where it
    gives no curve), the motions with resurrections, the responses sensitive to the tolerance."""
    data = study.data
    unit = LEVELS[study.config["measure"]] or "(scale factor)"
    motions, responses = data.sizes["motion"], data.sizes["motion"] * data.sizes["level"] * data.sizes["sign"]
    lines = []
    for part in ("bare", "damper"):
        a = data.sel(part=part)
        status = FIT_STATUSES[int(a["fit_status"])]
        text = status.replace("_", " ")
        if status in FITTED:
            median, low, high = (float(a[k]) for k in ("median", "median_low", "median_high"))
            dispersion, d_low, d_high = (float(a[k]) for k in ("dispersion", "dispersion_low", "dispersion_high"))
            text = (
                f"median {median:.4g} {unit}, dispersion {dispersion:.3g} (90 % intervals {low:.4g} to "
                f"{high:.4g}, {d_low:.3g} to {d_high:.3g}), {text}"
            )
        lines.append(
            f"{study.kind}, {part}: {text}; {int((a['reversals'] > 0).sum())} of {motions} motions "
            "overturn the block at a level and not at a higher one; "
            f"{int(a['sensitive_responses'].sum())} of {responses} responses sensitive to the tolerance"
        )
    return lines


def _cmd_demo(args) -> int:
    """The damper as built: stops at the block's edges beside the paper's unlimited guide (full maps and spectra,
    both directions), the design answer, and ``Omega*`` across geometries; each on its command's default grids."""
    setting, execution, out = setting_from(args), execution_from(args), out_from(args)
    tuning = tuning_from(args)
    dampers = (("", replace(tuning, stops=True)), ("-unlimited", replace(tuning, stops=False, stroke=None)))
    start = time.perf_counter()
    runs = out / "runs"
    for suffix, damper in dampers:
        # Full maps: the figures tell every saved cell's stroke, which an adaptive map computes at its edges only.
        study = overturning_map(
            setting, damper, grid_from("Omega", MAP_OMEGA), grid_from("beta", MAP_BETA), execution, runs=runs, full=True
        )
        _report(study, out, f"map{suffix}")
        _print_map(study)
    for suffix, damper in dampers:
        Omega, beta = grid_from("Omega", SPECTRUM_OMEGA), grid_from("beta", SPECTRUM_BETA)
        study = minimum_overturning_spectrum(setting, damper, Omega, beta, execution, runs=runs, **_tol(args))
        _report(study, out, f"spectrum{suffix}")
        _print_spectrum(study)
    _vertical_spectra(setting, replace(tuning, stops=True), execution, out, runs, **_tol(args))
    study = design(
        setting,
        grid_from("Omega", DESIGN_OMEGA),
        grid_from("beta", DESIGN_BETA),
        execution,
        gamma=tuning.gamma,
        h=tuning.h,
        runs=runs,
        **_tol(args),
    )
    _report(study, out)
    _print_design(study)
    grids = [grid_from(name, default) for name, default in (("lam", LAM_GRID), ("p", P_GRID), ("Omega", OMEGA_GRID))]
    study = threshold_map(
        *grids,
        execution,
        gamma=tuning.gamma,
        zeta=tuning.zeta,
        h=tuning.h,
        rtol=setting.rtol,
        t_after=setting.t_after,
        backend=setting.backend,
        runs=runs,
        **_tol(args),
    )
    _report(study, out)
    _print_threshold_map(study)
    print(
        f"demo: done in {time.perf_counter() - start:.0f} s; figures in {out}/ (map, map-unlimited, spectrum, "
        "spectrum-unlimited, spectrum-vertical, design, threshold .png/.pdf)"
    )
    return 0


def _vertical_spectra(setting: Setting, damper: Tuning, execution: Execution, out: Path, runs: Path, **tol) -> None:
    """The demo's spectra of the block alone and with ``damper`` under pulses with the vertical ratios
    :data:`VERTICAL_RATIOS` (in phase), both directions, saved as ``spectrum-vertical-<ratio>`` (``0p5`` for 0.5)
    and drawn together as ``spectrum-vertical.png``."""
    studies = []
    for ratio in VERTICAL_RATIOS:
        Omega, beta = grid_from("Omega", VERTICAL_OMEGA), grid_from("beta", VERTICAL_BETA)
        vertical = replace(setting, vertical_ratio=ratio, vertical_phase=0.0)
        study = minimum_overturning_spectrum(
            vertical, damper, Omega, beta, execution, runs=runs, directions="both", **tol
        )
        # No dot in a stem: rocking redraw and load read "spectrum-vertical-0.5" as the stem of a ".5" file.
        save(study, out, f"spectrum-vertical-{ratio:g}".replace(".", "p"))
        studies.append(study)
    paths = draw_vertical_spectra(studies, out)
    print(
        f"spectrum, vertical ratios {', '.join(f'{r:g}' for r in VERTICAL_RATIOS)}: wrote {', '.join(map(str, paths))}"
    )


def _cmd_redraw(args) -> int:
    for path in args.paths:
        written = redraw(path)
        print(f"redrew {', '.join(str(p) for p in written)}")
    return 0


#: Warnings of a study, and of implausible inputs, that the command line shows as one line each, like its errors.
STUDY_WARNINGS = (TileWarning, UndeterminedWarning, PlausibilityWarning, FitWarning)


@contextmanager
def warnings_in_one_line(command: str) -> Iterator[None]:
    """Show the warnings of :data:`STUDY_WARNINGS` as ``rocking COMMAND: warning: ...``, one line each."""
    default = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        if issubclass(category, STUDY_WARNINGS):
            print(f"rocking {command}: warning: {message}", file=sys.stderr)
        else:
            default(message, category, filename, lineno, file, line)

    with warnings.catch_warnings():  # restores showwarning on leaving
        warnings.showwarning = show
        yield


def _guarded(command):
    """``command(args)`` with bad parameters reported in one line (exit 2), a full disk too (exit 1: the finished
    tiles are kept, nothing partial is published) and Ctrl-C as a resumable stop (130)."""

    def run(args) -> int:
        rerun = getattr(args, "rerun", None)
        token = CURRENT.set({"command": command_record(args), "rerun": rerun})
        try:
            with warnings_in_one_line(args.command):
                return command(args)
        except ParameterError as exc:
            print(f"rocking {args.command}: error: {exc}", file=sys.stderr)
            return 2
        except DiskFull as exc:
            kept = "finished tiles kept" if exc.kept is None else f"{exc.kept} tiles kept"
            print(
                f"rocking {args.command}: error: disk full writing {exc.path}: {kept}, rerun to resume", file=sys.stderr
            )
            return 1
        except Interrupted as exc:
            print(
                f"rocking {args.command}: interrupted: {exc.kept} of {exc.total} tiles kept in {exc.folder}; "
                "run the same command again to resume",
                file=sys.stderr,
            )
            return 130
        except KeyboardInterrupt:  # outside the tiles (checks, saving): nothing to resume from yet
            print(f"rocking {args.command}: interrupted; run the same command again to resume", file=sys.stderr)
            return 130
        finally:
            CURRENT.reset(token)

    return run


def _study_parser(subparsers, name: str, text: str) -> argparse.ArgumentParser:
    """A study's parser, its description saying which block it uses; the block options first."""
    p = add_parser(subparsers, name, text, f"{text[:1].upper()}{text[1:]}. {block_help()}")
    add_block_options(p)
    return p


def add_study_commands(subparsers) -> None:
    """Add ``map``, ``spectrum``, ``optimize``, ``demo`` and ``redraw`` to the ``rocking`` subparsers."""
    p = _study_parser(subparsers, "map", "overturning map over (Omega, beta), block alone and with a damper")
    _add_damper(p, tuned=True, searched=False)
    _add_variant(p)
    _add_grid(p, "Omega", MAP_OMEGA, "pulse frequency ratios omega_g / p")
    _add_grid(p, "beta", MAP_BETA, "pulse amplitude ratios a_g / (g tan alpha)")
    tile = python_default(overturning_map, "tile")
    p.add_argument(
        "--tile", type=int, nargs=2, metavar=("NOMEGA", "NBETA"), help=f"cells per tile (default {tile[0]} {tile[1]})"
    )
    p.add_argument(
        "--coarse",
        type=int,
        metavar="STEP",
        help="coarse step of the adaptive map, a power of two: every STEP-th cell is computed, then the map is "
        "refined where neighbouring outcome classes differ, and verified (--verify) "
        f"({default_text(overturning_map, 'coarse')})",
    )
    p.add_argument(
        "--verify",
        type=int,
        metavar="STEP",
        help="first step of the verification of the adaptive map, a power of two up to --coarse, 0: none: every "
        "region of one class that holds STEP x STEP cells is found, smaller ones near the class boundaries "
        "(default: the coarse step)",
    )
    p.add_argument("--full", action="store_const", const=True, help="compute every cell (default: the adaptive map)")
    _add_directions(p)
    _add_pulse(p)
    _add_vertical(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_map))

    p = _study_parser(subparsers, "spectrum", "minimum overturning amplitude beta_min(Omega), with safe windows")
    _add_damper(p, tuned=True, searched=False)
    _add_variant(p)
    _add_grid(p, "Omega", SPECTRUM_OMEGA, "pulse frequency ratios")
    _add_grid(p, "beta", SPECTRUM_BETA, "scan amplitudes (the step bounds the windows seen)")
    _add_tol(p)
    p.add_argument(
        "--coarse",
        type=int,
        metavar="STEP",
        help="adaptive beta scans of coarse step STEP, a power of two: every STEP-th amplitude is computed, then "
        "bisections where neighbouring outcome classes differ, and a verification; features narrower than STEP "
        "amplitudes away from a class change can be missed, and are on the default grids (16 is about 4.6 times "
        "fewer scan responses there; default: every amplitude)",
    )
    _add_directions(p)
    _add_pulse(p)
    _add_vertical(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_spectrum))

    p = _study_parser(subparsers, "optimize", "optimal damper period and best gain against Omega; threshold Omega*")
    _add_damper(p, tuned=False, searched=True)
    _add_grid(p, "Omega", OPTIMIZE_OMEGA, "pulse frequency ratios")
    _add_grid(p, "beta", OPTIMIZE_BETA, "scan amplitudes of every beta_min")
    _add_search(p, TM_GRID, optimal_damper)
    _add_tol(p)
    _add_directions(p)
    _add_pulse(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_optimize))

    p = _study_parser(
        subparsers, "design", "one damper with stops for a band of pulses: the best worst gain, in SI units"
    )
    g = p.add_argument_group("damper", "As rocking.design: the mass budget and the stroke; the search ranges.")
    g.add_argument("--gamma", type=float, help=f"mass budget m/M ({default_text(design, 'gamma')})")
    g.add_argument(
        "--stroke", type=float, help="half-stroke L of the stops, m, in (0, B/2) (default B/2 minus the pads' 20 mm)"
    )
    g.add_argument("--h", type=float, help=f"height of the guide above the block, m ({default_text(design, 'h')})")
    _add_search(g, DESIGN_TM_GRID, design)
    g.add_argument(
        "--zeta-grid",
        nargs=3,
        metavar=("MIN", "MAX", "N"),
        help=f"coarse log grid of the damping ratio (default {ZETA_GRID[0]:g} {ZETA_GRID[1]:g} {ZETA_GRID[2]})",
    )
    _add_grid(p, "Omega", DESIGN_OMEGA, "the band of pulse frequency ratios")
    _add_grid(p, "beta", DESIGN_BETA, "scan amplitudes of every beta_min")
    _add_tol(p)
    _add_directions(p)
    _add_pulse(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_design))

    p = add_parser(
        subparsers,
        "threshold",
        "threshold frequency Omega* over block geometries, unlimited guide and stops",
        "The threshold frequency Omega* (above it the best damper gains less than 1 %) over a grid of "
        "slenderness lambda = H/B and size p, for the unlimited guide and the stops at the block's edges, both "
        "directions; the beta scan rises until the block overturns or the pulse passes --a-max g.",
    )
    _add_grid(p, "lam", LAM_GRID, "slenderness H/B of the blocks")
    _add_grid(p, "p", P_GRID, "size p = sqrt(3 g / 4 R) of the blocks, rad/s")
    _add_grid(p, "Omega", OMEGA_GRID, "pulse frequency ratios scanned at each geometry")
    g = p.add_argument_group("blocks and damper", "As rocking.study.threshold.threshold_map.")
    g.add_argument(
        "--e-ratio", type=float, help=f"eccentricity e/B of every block ({default_text(threshold_map, 'e_ratio')})"
    )
    g.add_argument("--gamma", type=float, help=f"mass ratio m/M ({default_text(threshold_map, 'gamma')})")
    g.add_argument("--zeta", type=float, help=f"damping ratio ({default_text(threshold_map, 'zeta')})")
    g.add_argument(
        "--h", type=float, help=f"height of the guide above the block, m ({default_text(threshold_map, 'h')})"
    )
    _add_search(g, THRESHOLD_TM_GRID, threshold_map)
    g.add_argument(
        "--a-max", type=float, help=f"bound of the ground acceleration, in g ({default_text(threshold_map, 'a_max')})"
    )
    _add_tol(p)
    _add_directions(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_threshold))

    p = _study_parser(
        subparsers,
        "demo",
        "the damper as built: maps and spectra with stops and unlimited, both directions; design; Omega*",
    )
    _add_damper(p, tuned=True, searched=False, stops=False)
    _add_tol(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_demo))

    for name, text in (
        ("ida", "incremental dynamic analysis: every record at every scale factor, with and without the damper"),
        (
            "fragility",
            "fragility curves: the probability of overturning against an intensity measure, "
            "over a suite of records or of stochastic motions",
        ),
    ):
        p = _study_parser(subparsers, name, text)
        _add_damper(p, tuned=True, searched=False)
        _add_variant(p)
        g = p.add_argument_group(
            "motions",
            "As rocking.study.suite.Suite.from_files, Suite.stochastic or "
            "Suite.from_pulses (each pulse its class's from_period(a_g, T_g, ...)).",
        )
        g.add_argument(
            "--motions",
            nargs="+",
            metavar="FILE[:UNIT]",
            help="records: PEER NGA .AT2, or 'time, a' columns; FILE:UNIT gives a file its own unit of "
            f"acceleration ({', '.join(UNITS)}), e.g. a.AT2 b.txt:cm/s2",
        )
        g.add_argument(
            "--unit",
            choices=tuple(UNITS),
            help="unit of the accelerations of the text or CSV records given without their own "
            "(default: the one each header states)",
        )
        g.add_argument("--stochastic", type=int, metavar="N", help="N motions of the stochastic site model")
        g.add_argument("--seed", type=int, help="seed of the stochastic motions (default 0)")
        for option in SITE_OPTIONS:
            g.add_argument(
                f"--{option.replace('_', '-')}",
                type=float,
                help=f"site model: {option} (default {getattr(DEFAULT_SITE, option):g})",
            )
        g.add_argument(
            "--vertical-ratio",
            type=float,
            metavar="R",
            help="a vertical component of the --stochastic motions, > 0 up: R times a record of the same site "
            "model from its own noise, in [0, 10] (docs/model.md section 14; default none)",
        )
        g.add_argument(
            "--pulses",
            choices=[f.replace("_", "-") for f in PULSES],
            help="a suite of analytic pulses of this family, one per --periods value",
        )
        g.add_argument("--periods", nargs="+", type=float, metavar="T", help="periods 2 pi / omega_g of --pulses, s")
        g.add_argument("--amplitude", type=float, help="amplitude a_g of --pulses, m/s2 (default 1 g)")
        g.add_argument("--gamma-mp", type=float, help="oscillations gamma of --pulses mp, > 1")
        g.add_argument("--nu", type=float, help="phase nu of --pulses mp, rad (default 0)")
        if name == "ida":
            _add_levels(p, "scales", IDA_SCALES, "scale factors of every record")
        else:
            p.add_argument(
                "--im",
                choices=tuple(LEVELS)[1:],
                default="pga",
                help="intensity measure (default pga; amplitude: the a_g of --pulses)",
            )
            _add_levels(p, "levels", FRAGILITY_LEVELS, "levels of the intensity measure, SI units (m/s2 for pga)")
        _add_directions(p)
        _add_solver(p)
        _add_check(p)
        p.set_defaults(func=_guarded(_cmd_ida))

    p = add_parser(subparsers, "redraw", "redraw figures from saved study data, without recomputing")
    p.add_argument("paths", nargs="+", help="a saved study (.nc, .json or their stem) or a folder of them")
    p.set_defaults(func=_guarded(_cmd_redraw))
