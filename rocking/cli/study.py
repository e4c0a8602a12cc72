"""The study subcommands of ``rocking``: one per kind of :data:`rocking.study.kinds.KINDS`, ``demo``, ``redraw``.

:func:`add_study_commands` adds them to the ``rocking`` parser's subparsers;
each sets ``func(args) -> exit code``. A study writes ``<out>/<kind>.nc``,
``.csv``, ``.json`` and ``.png`` (its figure also as ``.pdf`` with ``--pdf``, in other formats with ``--formats``),
and keeps its finished tiles in ``<out>/runs`` so that an interrupted run resumes where it stopped.

A kind's command is data of its registry entry (:class:`rocking.study.kinds.Command`): its help, its option
groups by name, the positional arguments of its driver and its summary lines. The option groups are the
table :data:`GROUPS` here: each adds its options to the parser and turns the options given into the driver's
arguments; :func:`run_study` runs any kind with them, and prints its summary lines (``map_lines``,
``spectrum_lines``, ...: each ``describe(study) -> list[str]``, the command line's words, named by the entry).

Each command computes what the Python study API computes with the options given and nothing
else (:mod:`.options`): ``rocking map ...`` computes what
``rocking.overturning_map(Setting(block, ...), Tuning(...), Grid(...), Grid(...))``
computes, with the same defaults. The grids (and the mass ratios of
``optimize``) have no default in Python; the command line's are the registry's.

Bad parameters end with a one-line message naming the parameter and its valid
range and exit code 2 (argparse's own errors, e.g. an unknown option, too).
"""

from __future__ import annotations

import argparse
import re
import sys
import time
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path

import numpy as np

from ..model.params import ParameterError
from ..model.plausibility import PlausibilityWarning
from ..model.records import UNITS
from ..model.stochastic import DEFAULT_SITE
from ..plot import DEFAULT_FORMATS, FORMATS, check_formats
from ..sim.accuracy import CHECKS
from ..study.api import with_omega_ratio
from ..study.config import BACKENDS, PULSES, Grid, Setting, Tuning, Variant, omega_grid, pulse_grids
from ..study.design import DesignWarning, design
from ..study.design import verdict as design_verdict
from ..study.directions import DIRECTIONS
from ..study.files import DiskFull, make_folder, name_lock, no_space
from ..study.fragility import FITTED, MEDIAN_PLACES, FitWarning, median_words

# The drivers of the kinds are looked up in this module when a command runs (_driver): imported here by name.
from ..study.ida import LEVELS, incremental_dynamic_analysis  # noqa: F401
from ..study.kinds import (
    DESIGN_BETA,
    DESIGN_OMEGA,
    KINDS,
    MAP_BETA,
    MAP_OMEGA,
    SPECTRUM_BETA,
    SPECTRUM_OMEGA,
    Kind,
)
from ..study.optimize import USELESS_GAIN, EdgeWarning, check_gammas
from ..study.overturning_map import TMaxWarning, UndeterminedWarning, overturning_map
from ..study.result import Study
from ..study.spectrum import adaptive_scans, gain_summary, minimum_overturning_spectrum
from ..study.spectrum import envelope as spectrum_envelope
from ..study.storage import save
from ..study.suite import Suite, split_unit, suite_of
from ..study.threshold import LAM_GRID, OMEGA_GRID, P_GRID, threshold_map, thresholds
from ..study.tiles import Execution, Interrupted, TileWarning
from ..study.vocabulary import FIT_STATUSES, REGIMES, regime_label
from . import preload
from .options import (
    acceleration,
    add_block_options,
    add_floor_options,
    add_parser,
    block_from,
    block_help,
    default_text,
    flag,
    flags,
    flags_of,
    floor_from,
    given,
    named_as_flag,
    numbers_text,
    params_from,
    python_default,
)
from .rerun import CURRENT, check_same, command_record

#: The libraries a study's command makes its data and figures with, loaded (:func:`rocking.cli.preload`) once its
#: options are checked.
STUDY_LIBRARIES = ("xarray", "rocking.plot.figures")

#: The demo's spectra under a vertical component: its ratios and modest grids (about 20 s on 2 cores).
VERTICAL_RATIOS = (0.0, 0.5, 1.0)
VERTICAL_OMEGA, VERTICAL_BETA = (0.5, 15.0, 30), (0.5, 15.0, 59)

#: Options of the stochastic site model (rocking.model.stochastic.SiteModel): what each is, and its unit (its
#: docstring's, Rezaeian and Der Kiureghian 2008).
SITE_HELP = {
    "arias": ("expected Arias intensity I_a", "m/s"),
    "d595": ("significant duration D_5-95, from 5 %% to 95 %% of I_a", "s"),
    "t_mid": ("time at which 45 %% of I_a is reached", "s"),
    "f_mid": ("filter frequency at t_mid", "Hz"),
    "f_slope": ("rate of change of the filter frequency", "Hz/s"),
    "zeta_f": ("damping ratio of the filter, in (0, 1)", ""),
    "f_c": ("corner of the high-pass filter", "Hz"),
    "dt": ("time step of the samples", "s"),
    "duration": ("length of each record", "s"),
}
SITE_OPTIONS = tuple(SITE_HELP)


def _site_help(option: str) -> str:
    """The help of a site model's option: what it is, its unit and its default (:data:`DEFAULT_SITE`'s)."""
    meaning, unit = SITE_HELP[option]
    default = f"{getattr(DEFAULT_SITE, option):g}"
    return (
        f"site model: {meaning}, {unit} (default {default} {unit})"
        if unit
        else f"site model: {meaning} (default {default})"
    )


#: The options of a suite of pulses besides ``--pulses``.
PULSE_SUITE_OPTIONS = ("periods", "amplitude", "gamma_mp", "nu")

#: Options that set the omd damper (a Tuning), refused with a model variant.
DAMPER_OPTIONS = ("gamma", "Tm_ratio", "omega_ratio", "zeta", "h", "stops")

#: Values of the option groups that make the study's Setting with the block, when its driver takes one.
SETTING = ("rtol", "t_after", "backend", "pulse", "gamma_mp", "nu", "vertical_ratio", "vertical_phase", "floor")


# --- options -------------------------------------------------------------------------


def _add_solver(p: argparse.ArgumentParser, backend: str | None = None) -> None:
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
    default = default_text(Setting, "backend") if backend is None else f"default {backend}"
    g.add_argument("--backend", help=f"{' or '.join(BACKENDS)} ({default})")
    g.add_argument(
        "--workers", type=int, help="local workers (default: all cores): threads on the C back end, processes on NumPy"
    )
    g.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask cluster at ADDRESS (tcp://host:port)")
    g.add_argument("--dask-workers", type=int, metavar="N", help="run on a local Dask cluster of N worker processes")
    g.add_argument("--out", default="out", help="output folder (default out); finished tiles are kept in OUT/runs")
    _add_formats(g)
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    g.add_argument(
        "--config",
        metavar="SAVED.json",
        help="rerun the study saved in SAVED.json with its options (those given here win: --out, --workers, ...)",
    )


def _add_formats(p) -> None:
    p.add_argument(
        "--formats",
        metavar="LIST",
        help=f"formats of the figure, comma-separated, of {', '.join(FORMATS)} (default {','.join(DEFAULT_FORMATS)})",
    )
    p.add_argument("--pdf", action="store_true", help="also write the figure as PDF (as --formats png,pdf)")


def formats_from(args) -> tuple[str, ...]:
    """The figure's formats that ``--formats`` and ``--pdf`` ask for (default :data:`rocking.plot.DEFAULT_FORMATS`)."""
    formats = DEFAULT_FORMATS if args.formats is None else check_formats(args.formats.split(","), "--formats")
    return formats + ("pdf",) if args.pdf and "pdf" not in formats else formats


def _add_check(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--check",
        choices=CHECKS,
        help="'tolerance': run every response again down a ladder of tolerances and flag the sensitive ones, as "
        "rocking simulate --check (default for records and --stochastic; 'none' for --pulses)",
    )


def _add_damper(
    p: argparse.ArgumentParser, *, tuned: bool, searched: bool, stops: bool = True, gammas: tuple = (), source=Tuning
) -> None:
    """Damper options: one damper (``tuned``: a Tuning) and/or the mass ratios of the optimisation (``searched``,
    ``gammas`` by default); ``source``: the Python call whose defaults of ``zeta`` and ``h`` the help shows."""
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
            default=list(gammas),
            help=f"mass ratios of the optimal damper (default {' '.join(map(str, gammas))}); "
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


#: The alternatives in SI units of the grids of pulses: what each gives, evenly spaced (pulse_grids).
SI_GRIDS = {
    "T_g": "pulse periods T_g = 2 pi / omega_g, s, evenly spaced",
    "a_g": "pulse amplitudes a_g, m/s^2, or g with a g suffix (0.5g), evenly spaced",
}


def _add_grid(p: argparse.ArgumentParser, name: str, default: tuple, text: str, si: str | None = None) -> None:
    """``--NAME MIN MAX N`` (default ``default``); with ``si``, its alternative in SI units (``--T-g``,
    ``--a-g``), whose use leaves ``--NAME`` at None (:func:`_grid_values` applies the default)."""
    p.add_argument(
        f"--{name}",
        nargs=3,
        metavar=("MIN", "MAX", "N"),
        default=None if si else default,
        help=f"{text} (default {default[0]:g} {default[1]:g} {default[2]})",
    )
    if si:
        p.add_argument(flag(si), nargs=3, metavar=("MIN", "MAX", "N"), help=f"{SI_GRIDS[si]}: in place of --{name}")


def _grid_values(args, params: dict) -> dict:
    """The grid of ``--NAME``, or of its alternative in SI units when the kind has one (both kept, None if not
    given, for :func:`rocking.study.config.pulse_grids` to refuse both; the default when neither is given)."""
    name, si = params["name"], params.get("si")
    values = getattr(args, name)
    if si is None:
        return {name: grid_from(name, values)}
    alternative = getattr(args, si)
    if values is None and alternative is None:
        values = params["default"]
    return {
        name: None if values is None else grid_from(name, values),
        si: None if alternative is None else grid_from(si, alternative),
    }


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


def _add_frequency(p: argparse.ArgumentParser, default: float) -> None:
    """``--Omega X`` or ``--T-g X``: the one frequency of every pulse of a regime map."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("--Omega", type=float, help=f"every pulse's frequency ratio omega_g / p (default {default:g})")
    g.add_argument("--T-g", type=float, help="every pulse's period T_g = 2 pi / omega_g, s: in place of --Omega")


def _frequency(args, params: dict) -> dict:
    """``Omega`` of a regime map: ``--Omega``, or ``--T-g`` for the block of the options, or the default."""
    if args.T_g is None:
        return {"Omega": params["default"] if args.Omega is None else args.Omega}
    try:
        periods = Grid.of("T_g", [args.T_g])
    except ParameterError as exc:
        raise ParameterError(str(exc).replace("T_g", "--T-g")) from None
    return {"Omega": float(omega_grid(block_from(args), periods).values()[0])}


def _add_tol(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--beta-tol",
        type=float,
        help=f"relative tolerance of the bisection on beta ({default_text(minimum_overturning_spectrum, 'tol')})",
    )


# --- building the study's objects from the options -----------------------------------------


def grid_from(name: str, values, *, log: bool = False) -> Grid:
    """A :class:`Grid` from the three strings ``MIN MAX N`` of the option of keyword ``name``; those of ``a_g``
    are accelerations in m/s^2 or in g (:func:`~.options.acceleration`)."""
    number = partial(acceleration, name=flag(name)) if name == "a_g" else float
    try:
        low, high, n = float(number(values[0])), float(number(values[1])), int(values[2])
    except ParameterError:
        raise
    except (TypeError, ValueError):
        raise ParameterError(
            f"{flag(name)} takes MIN MAX N: two numbers and an integer (got {' '.join(map(str, values))})"
        ) from None
    return Grid(name, low, high, n, log=log)


def setting_from(args) -> Setting:
    """The study's :class:`Setting` from the options given (``--pulse ricker-anti`` is ``pulse="ricker_anti"``)."""
    # ida and fragility have no --pulse: their --gamma-mp and --nu shape the pulses of their suite.
    # map and spectrum: their pulses' vertical component (ida's and fragility's --vertical-ratio is their suite's).
    pulse = _pulse(args, {}) | given(args, ("vertical_ratio", "vertical_phase")) if "pulse" in vars(args) else {}
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


def _suite_from(args) -> Suite:
    """The motions of ``ida``/``fragility``: ``--motions FILE[:UNIT]...`` (with ``--vertical-motions
    FILE[:UNIT]...``), ``--stochastic N --seed S`` (site options) or ``--pulses FAMILY --periods T...``, as
    :func:`rocking.study.suite.suite_of` makes them."""
    site = given(args, SITE_OPTIONS)
    motions = None if args.motions is None else [split_unit(m) for m in args.motions]
    vertical = None if args.vertical_motions is None else [split_unit(v) for v in args.vertical_motions]
    try:
        return suite_of(
            motions,
            vertical_motions=vertical,
            **given(args, ("unit", "stochastic", "seed", "vertical_ratio", "pulses", *PULSE_SUITE_OPTIONS)),
            site=site or None,
            g=block_from(args).g,
        )
    except ParameterError as exc:
        raise ParameterError(_as_flags(str(exc))) from None


def _as_flags(message: str) -> str:
    """A message of :func:`suite_of` naming the Python keywords of the options, with the command line's flags."""
    message = re.sub(r"\bsite\b(?!\.)", "site options (" + flags(SITE_OPTIONS[:2]) + ", ...)", message)
    # vertical_motions last: in its flag, --vertical-motions, the word motions follows a hyphen and would be flagged.
    words = ("motions", "unit", "stochastic", "seed", "vertical_ratio", "pulses", *PULSE_SUITE_OPTIONS)
    for word in (*words, "vertical_motions"):
        message = re.sub(rf"\b{word}\b(?!\.)", flag(word), message)
    return message


# --- commands --------------------------------------------------------------------------


# --- the option groups of the study commands ------------------------------------------------


def _add_tile(p: argparse.ArgumentParser) -> None:
    tile = python_default(overturning_map, "tile")
    p.add_argument(
        "--tile", type=int, nargs=2, metavar=("NOMEGA", "NBETA"), help=f"cells per tile (default {tile[0]} {tile[1]})"
    )


def _add_refinement(p: argparse.ArgumentParser) -> None:
    """``--coarse``, ``--verify`` and ``--full`` of the adaptive map."""
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
        "region of one class that extends over --coarse cells along an axis (the verification computes the edges "
        "of the coarse blocks) or holds STEP x STEP cells is found, smaller ones near the class boundaries "
        "(default: the coarse step)",
    )
    p.add_argument("--full", action="store_const", const=True, help="compute every cell (default: the adaptive map)")


def _refinement(args, params: dict) -> dict:
    """``full=``, ``coarse=`` and ``verify=`` of a map, as given; --full refused with the others."""
    # argparse cannot say it: --coarse and --verify go together, and neither goes with --full.
    if args.full and (args.coarse is not None or args.verify is not None):
        raise ParameterError(
            "give --coarse/--verify (the steps of the adaptive refinement) or --full (every cell), not both"
        )
    return given(args, ("full", "coarse", "verify"))


def _add_design_damper(p: argparse.ArgumentParser, params: dict, kind: Kind) -> None:
    """The damper of ``design``: its mass budget and stroke; the ranges of its period and damping searched."""
    g = p.add_argument_group("damper", "As rocking.design: the mass budget and the stroke; the search ranges.")
    g.add_argument("--gamma", type=float, help=f"mass budget m/M ({default_text(kind.driver, 'gamma')})")
    g.add_argument(
        "--stroke", type=float, help="half-stroke L of the stops, m, in (0, B/2) (default B/2 minus the pads' 20 mm)"
    )
    g.add_argument("--h", type=float, help=f"height of the guide above the block, m ({default_text(kind.driver, 'h')})")
    _add_search(g, params["default"], kind.driver)
    zeta = params["zeta_grid"]
    g.add_argument(
        "--zeta-grid",
        nargs=3,
        metavar=("MIN", "MAX", "N"),
        help=f"coarse log grid of the damping ratio (default {zeta[0]:g} {zeta[1]:g} {zeta[2]})",
    )


def _add_threshold_damper(p: argparse.ArgumentParser, params: dict, kind: Kind) -> None:
    """The blocks' eccentricity and the damper of ``threshold``, and the bound of its scans."""
    g = p.add_argument_group("blocks and damper", "As rocking.study.threshold.threshold_map.")
    g.add_argument(
        "--e-ratio", type=float, help=f"eccentricity e/B of every block ({default_text(kind.driver, 'e_ratio')})"
    )
    g.add_argument("--gamma", type=float, help=f"mass ratio m/M ({default_text(kind.driver, 'gamma')})")
    g.add_argument("--zeta", type=float, help=f"damping ratio ({default_text(kind.driver, 'zeta')})")
    g.add_argument("--h", type=float, help=f"height of the guide above the block, m ({default_text(kind.driver, 'h')})")
    _add_search(g, params["default"], kind.driver)
    g.add_argument(
        "--a-max", type=float, help=f"bound of the ground acceleration, in g ({default_text(kind.driver, 'a_max')})"
    )


def _search(args) -> dict:
    """``Tm=`` (the log grid of ``--Tm-ratio``) and ``refine=`` of a study that searches the damper period."""
    Tm = {"Tm": grid_from("Tm-ratio", args.Tm_ratio, log=True)} if args.Tm_ratio is not None else {}
    return given(args, ("refine",)) | Tm


def _design_damper(args, params: dict) -> dict:
    zeta = {"zeta": grid_from("zeta", args.zeta_grid, log=True)} if args.zeta_grid is not None else {}
    return given(args, ("gamma", "stroke", "h")) | _search(args) | zeta


def _add_motions(p: argparse.ArgumentParser) -> None:
    """The suite of motions of ``ida`` and ``fragility``: records, stochastic motions or pulses."""
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
        "--vertical-motions",
        nargs="+",
        metavar="FILE[:UNIT]",
        help="the vertical record (> 0 up) of each of --motions, in their order: of its record's dt, taken as 0 "
        "after its end and cut at the record's, as rocking simulate --vertical; a scale factor scales both "
        "components, the intensity measure of a level is the horizontal record's (docs/model.md section 14)",
    )
    g.add_argument(
        "--unit",
        choices=tuple(UNITS),
        help="unit of the accelerations of the text or CSV records (and --vertical-motions) given without their own "
        "(default: the one each header states)",
    )
    g.add_argument("--stochastic", type=int, metavar="N", help="N motions of the stochastic site model")
    g.add_argument("--seed", type=int, help="seed of the stochastic motions (default 0)")
    for option in SITE_OPTIONS:
        g.add_argument(
            f"--{option.replace('_', '-')}",
            type=float,
            help=_site_help(option),
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


def _add_im(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--im",
        choices=tuple(LEVELS)[1:],
        default="pga",
        help="intensity measure (default pga; amplitude: the a_g of --pulses)",
    )


def _levels(args, params: dict) -> dict:
    """``levels=`` from ``--NAME MIN MAX N`` or ``--NAME-log MIN MAX N``, and the measure of the levels if fixed."""
    name = params["name"]
    log = getattr(args, f"{name}_log")
    grid = grid_from(name, getattr(args, name)) if log is None else grid_from(f"{name}-log", log, log=True)
    return {"levels": grid} | ({"measure_name": params["measure"]} if "measure" in params else {})


def _pulse(args, params: dict) -> dict:
    """The pulse family of the Setting (``--pulse ricker-anti`` is ``pulse="ricker_anti"``)."""
    pulse = given(args, ("pulse", "gamma_mp", "nu"))
    if "pulse" in pulse:
        pulse["pulse"] = pulse["pulse"].replace("-", "_")
    return pulse


def _floor(args) -> dict:
    """``floor=`` of the Setting from ``--mu`` and ``--mu-k``, when given."""
    floor = floor_from(args)
    return {} if floor is None else {"floor": floor}


def _given(*names: str) -> Callable[[argparse.Namespace, dict], dict]:
    """The driver's keywords ``names``, those given, by the same names as the options."""
    return lambda args, params: given(args, names)


@dataclass(frozen=True)
class Group:
    """An option group of the study commands, named by the kinds' :class:`~rocking.study.kinds.Command`.

    Attributes
    ----------
    add : callable
        ``add(parser, params, kind)``: adds its options (``params``: what the kind's entry gives the group).
    collect : callable
        ``collect(args, params) -> dict``: the driver's arguments from the options given, by name (a
        ParameterError naming the flag for a bad one); ``"setting"`` is made from ``block``, the pulse and the
        solver's values (:data:`SETTING`) when the driver takes one.
    """

    add: Callable[[argparse.ArgumentParser, dict, Kind], None]
    collect: Callable[[argparse.Namespace, dict], dict]


#: The option groups of the study commands, by the names :data:`rocking.study.kinds.KINDS` gives them.
GROUPS = {
    "block": Group(lambda p, params, kind: add_block_options(p), lambda args, params: {"block": block_from(args)}),
    "damper": Group(
        lambda p, params, kind: _add_damper(
            p,
            tuned=params.get("tuned", False),
            searched=params.get("searched", False),
            gammas=params.get("gammas", ()),
            source=Tuning if params.get("tuned") else kind.driver,
        ),
        lambda args, params: (
            {"damper": damper_from(args)}
            if params.get("tuned")
            else {"gammas": check_gammas(args.gammas, "--gammas"), **given(args, ("zeta", "h", "stops"))}
        ),
    ),
    # --model and --param make the damper: damper_from reads them.
    "variant": Group(lambda p, params, kind: _add_variant(p), lambda args, params: {}),
    "design damper": Group(_add_design_damper, _design_damper),
    "threshold damper": Group(
        _add_threshold_damper,
        lambda args, params: given(args, ("e_ratio", "gamma", "zeta", "h", "a_max")) | _search(args),
    ),
    "search": Group(
        lambda p, params, kind: _add_search(p, params["default"], kind.driver), lambda a, params: _search(a)
    ),
    "grid": Group(
        lambda p, params, kind: _add_grid(p, params["name"], params["default"], params["help"], params.get("si")),
        _grid_values,
    ),
    "levels": Group(lambda p, params, kind: _add_levels(p, params["name"], params["default"], params["help"]), _levels),
    "tile": Group(
        lambda p, params, kind: _add_tile(p),
        lambda args, params: {"tile": tuple(args.tile)} if args.tile is not None else {},
    ),
    "refinement": Group(lambda p, params, kind: _add_refinement(p), _refinement),
    "tol": Group(lambda p, params, kind: _add_tol(p), lambda args, params: _tol(args)),
    "directions": Group(lambda p, params, kind: _add_directions(p), _given("directions")),
    "pulse": Group(lambda p, params, kind: _add_pulse(p), _pulse),
    "vertical": Group(lambda p, params, kind: _add_vertical(p), _given("vertical_ratio", "vertical_phase")),
    "motions": Group(lambda p, params, kind: _add_motions(p), lambda args, params: {"suite": _suite_from(args)}),
    "im": Group(lambda p, params, kind: _add_im(p), lambda args, params: {"measure_name": args.im}),
    # A kind's own default back end (the regime map's: one that follows friction) beside Setting's.
    "solver": Group(
        lambda p, params, kind: _add_solver(p, params.get("backend")),
        lambda args, params: (
            {k: v for k, v in params.items() if k == "backend"}
            | given(args, ("rtol", "t_after", "backend"))
            | {"execution": execution_from(args)}
        ),
    ),
    "frequency": Group(lambda p, params, kind: _add_frequency(p, params["default"]), _frequency),
    "check": Group(lambda p, params, kind: _add_check(p), _given("check")),
    "floor": Group(lambda p, params, kind: add_floor_options(p), lambda args, params: _floor(args)),
}


# --- commands --------------------------------------------------------------------------


def _report(study: Study, out: Path, formats: tuple[str, ...], name: str | None = None) -> list[Path]:
    """Save the study's data and its figure in ``formats`` as ``name`` (default: its kind); print where they are and
    how it ran."""
    current = CURRENT.get() or {}
    run = study.run
    kept = run["tiles_computed"] + run["tiles_reused"]
    # Data and figures under one lock on the name: another save of it into this folder waits, never mixes them.
    with name_lock(make_folder(out, "--out"), name or study.kind):
        try:
            paths = save(study, out, name, command=current.get("command"))
        except DiskFull as exc:
            raise DiskFull(exc.path, kept=kept) from None
        try:
            from ..plot.figures import draw  # matplotlib: here, not at the command's start

            paths += draw(study, out, name, formats)
        except Exception:
            # matplotlib's writers fail on a full disk in their own ways (an OSError, or an AttributeError of the PDF
            # stream): the free space tells. The data are published; the figures are redrawn by a rerun or redraw.
            if not no_space(out):
                raise
            raise DiskFull(out / f"{name or study.kind}.{' and .'.join(formats)}", kept=kept) from None
    print(
        f"{study.kind}: {run['tiles_computed']} tiles computed, {run['tiles_reused']} reused, "
        f"{run['wall_s']:.1f} s; wrote {', '.join(str(p) for p in paths)}"
    )
    chosen = study.config["directions"]
    signs = " and ".join(f"{s:+d}" for s in chosen["signs"])
    motions = "motions" if "suite" in study.config else "pulses"  # an IDA's or fragility's suite, else pulses
    print(f"{study.kind}: {motions} of sign {signs}: {chosen['reason']}")
    if current.get("rerun"):
        print(check_same(study, *current["rerun"]))
    return paths


def _driver(kind: Kind) -> Callable:
    """The kind's driver; those this module imports are looked up here, by name, when the command runs: a
    command's work starts at this one call (tests/test_rerun.py stops it there)."""
    return globals().get(kind.driver.__name__, kind.driver)


def run_study(name: str, args) -> int:
    """``rocking NAME``: the driver of the kind ``name`` called with the arguments its option groups make of the
    options given (:data:`GROUPS`), its study saved and drawn in ``--out`` and its summary lines printed."""
    kind = KINDS[name]
    values: dict = {}
    for group, params in kind.command.options:
        values |= GROUPS[group].collect(args, params)
    if "T_g" in values:  # the grids of pulses, each given as ratios or in SI units
        grids = {k: values.pop(k) for k in ("Omega", "beta", "T_g", "a_g")}
        values |= pulse_grids(values["block"], **grids, shown=flag)
    elif "a_g" in values:  # the amplitudes alone (a regime map's one frequency is its own option, --Omega)
        amplitudes = {k: values.pop(k) for k in ("beta", "a_g")}
        values["beta"] = pulse_grids(values["block"], Grid.of("Omega", [1.0]), **amplitudes, shown=flag)["beta"]
    if "setting" in kind.command.inputs:
        values["setting"] = Setting(values.pop("block"), **{k: values.pop(k) for k in SETTING if k in values})
    formats = formats_from(args)
    out = out_from(args)  # after every option is checked: bad parameters are refused before the folder is made
    preload(*STUDY_LIBRARIES)  # now that the study will run
    inputs = [values.pop(k) for k in kind.command.inputs]
    study = _driver(kind)(*inputs, runs=out / "runs", **values)
    _report(study, out, formats)
    _print(globals()[kind.command.describe](study))
    return 0


def _print(lines: list[str]) -> None:
    for line in lines:
        print(line)


# --- the summary lines of each kind (Command.describe) -------------------------------------


def map_lines(study: Study) -> list[str]:
    """What a map shows: the cells overturned, saved and lost; how an adaptive map was computed."""
    s = study.summary
    # An adaptive map fills in saved cells without computing the damper's stroke there: say how many.
    unknown_stroke = s.get("saved_stroke_not_computed", 0)
    lines = [
        f"map: {s['cells']} cells; overturned {s['bare_overturned']} alone, {s['damper_overturned']} with the damper; "
        f"saved {s['saved']} ({s['saved_past_edges']} only with the mass past the block's edge"
        + (
            f", {unknown_stroke} of unknown stroke: cells filled in by the adaptive map; --full computes them"
            if unknown_stroke
            else ""
        )
        + f"), lost {s['lost']}"
        + _per_part_words(s["bare_undetermined"], s["damper_undetermined"], "cells", "without a verdict")
        + _t_max_words(s["bare_t_max"], s["damper_t_max"], "cells")
    ]
    if "bare_slid" in s:  # a floor with friction
        lines.append(
            f"map: the base slid without overturning in {s['bare_slid']} cells alone, {s['damper_slid']} with the "
            "damper (their regime, u_max and u_end are in the data and the table)"
        )
    if "bare_flies_and_lands" in s:  # a vertical component (docs/model.md section 16)
        lines.append(
            f"map: the base flew in {s['bare_flies_and_lands'] + s['bare_flies_and_overturns']} cells alone "
            f"({s['bare_flies_and_overturns']} then overturned), "
            f"{s['damper_flies_and_lands'] + s['damper_flies_and_overturns']} with the damper "
            f"({s['damper_flies_and_overturns']} then overturned); flights, flight_time and jump_max are in the data"
        )
    refinement, run = study.config["refinement"], study.run
    if refinement["adaptive"]:
        lines += [
            f"map: adaptive (coarse step {refinement['coarse']}, verified from step {refinement['verify']}): "
            f"{run['responses']} of {run['responses_full_grid']} responses computed in {run['rounds']} rounds; "
            f"cells not computed take the outcome around them (--full computes every cell)",
            f"map: {s['guarantee']}",
            *_inferred_words(s),
        ]
    return lines


def _inferred_words(s: dict) -> list[str]:
    """What of an adaptive map's counts (its summary ``s``) rests on cells inferred, not computed, and how many
    more saved and lost cells those could hold: one line, or none where every cell was computed (or the map was
    saved by a version that did not count them)."""
    if not s.get("bare_inferred", 0) + s.get("damper_inferred", 0):
        return []
    return [
        f"map: inferred, not computed: {s['bare_inferred']} cells alone ({s['bare_overturned_inferred']} counted "
        f"overturned), {s['damper_inferred']} with the damper ({s['damper_overturned_inferred']} counted "
        f"overturned); saved {s['saved']}: {s['saved'] - s['saved_inferred']} computed, up to "
        f"{s['saved_possible']} more among the inferred cells; lost {s['lost']}: {s['lost'] - s['lost_inferred']} "
        f"computed, up to {s['lost_possible']} more among the inferred cells (where the guarantee above does not "
        "reach; --full computes every cell)"
    ]


def _t_max_words(bare: int, damper: int, what: str) -> str:
    """``"; N WHAT alone and M with the damper reached t_max"``, or nothing if none did: they count as not
    overturned (a short ``--t-after`` can make them)."""
    return _per_part_words(bare, damper, what, "reached t_max (counted as not overturned)")


def _per_part_words(bare: int, damper: int, what: str, happened: str) -> str:
    """``"; N WHAT alone and M with the damper HAPPENED"``, or nothing if neither count is above 0."""
    if not bare + damper:
        return ""
    return f"; {bare} {what} alone and {damper} with the damper {happened}"


def friction_lines(study: Study) -> list[str]:
    """What a regime map shows: the cells of each regime, Shenton's boundary, runs without a verdict."""
    s = study.summary
    counts = ", ".join(f"{s[name]} {regime_label(code)}" for code, name in REGIMES.items())
    lines = [f"friction: {s['cells']} cells: {counts}; Shenton's boundary mu = B/H = {s['B_over_H']:.3g}"]
    if s["undetermined"] or s["t_max"]:
        lines.append(
            f"friction: {s['undetermined']} cells without a verdict, {s['t_max']} reached t_max (follow them "
            "longer: --t-after)"
        )
    return lines


def spectrum_lines(study: Study) -> list[str]:
    """What a spectrum shows: the beta_min bracketed and the safe windows of each part, the damper's gain; that a
    spectrum saved by an earlier version was scanned adaptively."""
    lines = []
    for part in ("bare", "damper"):
        s = study.summary[part]
        lines.append(
            f"spectrum, {part}: beta_min bracketed at {s['bracketed']} frequencies, "
            f"not reached in the scan at {s['not_overturned_in_scan']}; {s['windows']} safe windows above beta_min"
            + (
                f"; {s['flown']} responses flew and landed to a verdict, beta_min's flew at {s['beta_min_flew']} "
                "frequencies"
                if "flown" in s
                else ""
            )
        )
    t_max = study.summary.get("t_max", {})
    if any(t_max.values()):
        lines.append("spectrum: " + _t_max_words(t_max["bare"], t_max["damper"], "responses")[2:])
    # The study's words; a spectrum saved before they were stored: the same, from its data.
    gain = study.summary.get("gain") or gain_summary(spectrum_envelope(study.data))
    if gain["frequencies"]:
        lines.append(f"spectrum: {gain['text']}")
    coarse = adaptive_scans(study.config)
    if coarse:
        lines.append(
            f"spectrum: saved by an earlier version with adaptive scans (coarse step {coarse}): amplitudes not "
            "computed took the outcome around them: a band of overturning amplitudes between them may have been "
            "missed, and beta_min be too high; run it again to scan every amplitude"
        )
    return lines


def threshold_lines(study: Study) -> list[str]:
    """The threshold frequency Omega* of an optimisation, for each mass ratio and the best over them."""
    Omega_max = float(study.data["Omega"].values[-1])
    lines = []
    for key, t in study.summary["Omega_star"].items():
        who = "best over gamma" if key == "best" else f"gamma = {key}"
        if t["status"] == "bracketed":
            lines.append(
                f"Omega* ({who}) = {t['Omega_star']:.3g}, between the scanned {t['low']:.3g} and {t['high']:.3g}"
            )
        elif t["status"] == "above_range":
            lines.append(
                f"Omega* ({who}) > {t['low']:.3g}: the damper still helps (gain >= {USELESS_GAIN:g}) at "
                f"Omega = {t['low']:.3g}, the highest frequency with a defined gain"
            )
        elif t["status"] == "below_range":
            lines.append(f"Omega* ({who}) <= {t['high']:.3g}: the damper does not help at any frequency scanned")
        else:
            lines.append(
                f"Omega* ({who}) unknown: no gain is defined (the bare block's beta_min is outside the beta scan)"
            )
        if t["defined_up_to"] is not None and t["defined_up_to"] < Omega_max:
            lines.append(
                f"  (gain undefined above Omega = {t['defined_up_to']:.3g}: the bare block does not overturn "
                "within the beta scan there; widen --beta to see further)"
            )
    return lines


def design_lines(study: Study) -> list[str]:
    """The damper designed, in SI units; its verdict (the study's, :func:`rocking.study.design.verdict`); how the
    stroke was used. Its warnings are the study's own (:data:`STUDY_WARNINGS`), shown as it runs."""
    s, d = study.summary, study.summary["damper"]
    lines = [
        f"design: m = {d['m_kg']:.4g} kg (gamma = {d['gamma']:g}), k_m = {d['k_m_N_per_m']:.4g} N/m, "
        f"c = {d['c_N_s_per_m']:.4g} N s/m (T_m = {d['T_m_s']:.4g} s, T_m p / 2 pi = {d['Tm_ratio']:.3g}, "
        f"zeta = {d['zeta']:.3g}); stops at L = {d['L_m']:.3g} m, k_b = {d['k_b_N_per_m']:.4g} N/m, "
        f"c_b = {d['c_b_N_s_per_m']:.4g} N s/m",
        # A design saved before the verdict was stored: the same words, from its summary.
        f"design: {s.get('verdict', design_verdict(s))['text']}",
    ]
    lines.append(
        f"design: stroke used at the pulses that overturn the block alone: up to {s['stroke_use_max']:.3g} L, "
        f"{s['stop_contacts_max']} stop contacts; {s['candidates_on_block']} of {s['candidates']} dampers tried "
        "keep their mass on the block"
    )
    if s["gain_undefined_at"]:
        lines.append(
            f"design: gain undefined at Omega = {numbers_text(s['gain_undefined_at'])} (the block alone does not "
            "overturn within the beta scan there; widen --beta)"
        )
    return lines


def threshold_map_lines(study: Study) -> list[str]:
    """Omega* of every geometry, for the unlimited guide and the stops; where the block alone is safe."""
    lines = []
    found, bound = thresholds(study.data), study.summary["a_max_g"]
    lams, ps = found["lam"].values, found["p"].values
    for kind in ("unlimited", "stops"):
        lines.append(
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
            lines.append(f"  lambda = {lam:g}: " + "; ".join(cells))
    Omega_max = float(found["Omega"].values[-1])
    for i, lam in enumerate(lams):
        clauses = "; ".join(
            safe_from_words(x, Omega_max) + f" (p = {p:g} rad/s)" for x, p in zip(found["safe_from"].values[i], ps)
        )
        lines.append(f"threshold: lambda = {lam:g}: the block alone survives every pulse up to {bound:g} g {clauses}")
    return lines


def safe_from_words(safe_from: float, Omega_max: float) -> str:
    """From which ``Omega`` on the block alone is safe, in words; nan (it overturns at the highest ``Omega``
    scanned) says so, not a number."""
    if np.isfinite(safe_from):
        return f"from Omega = {safe_from:.3g}"
    return f"from no Omega on: it still overturns at the highest scanned, Omega = {Omega_max:.3g}"


def fit_lines(study: Study) -> list[str]:
    """What an IDA or a fragility says of each part, one line each: the fitted lognormal (its status where it
    gives no curve), its median where it lies outside the levels tested, the motions with resurrections, the
    responses sensitive to the tolerance (or that they were not checked)."""
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
            text += _extrapolated(study, a)
        lines.append(
            f"{study.kind}, {part}: {text}; {int((a['reversals'] > 0).sum())} of {motions} motions "
            f"overturn the block at a level and not at a higher one; {_sensitive_words(study, a, responses)}"
        )
    return lines


def _extrapolated(study: Study, a) -> str:
    """``"; "`` and :func:`~rocking.study.fragility.median_words` of one part ``a`` of an IDA's data whose median
    lies outside the levels tested, else empty (a study saved without ``median_extrapolated`` too)."""
    if "median_extrapolated" not in a:
        return ""
    levels = a["level"].values
    fitted = levels > 0  # the levels the fit uses (rocking.study.ida._fit)
    place = MEDIAN_PLACES[int(a["median_extrapolated"])]
    words = median_words(
        place, float(a["median"]), levels[fitted], a["fraction"].values[fitted], LEVELS[study.config["measure"]]
    )
    return f"; {words}" if words else ""


def _sensitive_words(study: Study, a, responses: int) -> str:
    """How many of the ``responses`` of one part ``a`` of an IDA's data are sensitive to the tolerance, or that
    none was checked (the data then have no ``sensitive``) and why."""
    if "sensitive" not in study.data:
        check = study.config.get("check")
        why = {"none": "--check none", None: "pulses are checked only with --check tolerance"}.get(
            check, f"rtol {study.config['rtol']:g} has no tighter tolerance"
        )
        return f"sensitivity to the tolerance not checked ({why})"
    return f"{int(a['sensitive_responses'].sum())} of {responses} responses sensitive to the tolerance"


# --- demo and redraw, the command line's own; running a command ---------------------------


def _cmd_demo(args) -> int:
    """The damper as built: stops at the block's edges beside the paper's unlimited guide (full maps and spectra,
    both directions), the design answer, and ``Omega*`` across geometries; each on its command's default grids."""
    setting, execution, formats = setting_from(args), execution_from(args), formats_from(args)
    tuning, out = tuning_from(args), out_from(args)
    preload(*STUDY_LIBRARIES)
    dampers = (("", replace(tuning, stops=True)), ("-unlimited", replace(tuning, stops=False, stroke=None)))
    start = time.perf_counter()
    runs = out / "runs"
    for suffix, damper in dampers:
        # Full maps: the figures tell every saved cell's stroke, which an adaptive map computes at its edges only.
        study = overturning_map(
            setting, damper, grid_from("Omega", MAP_OMEGA), grid_from("beta", MAP_BETA), execution, runs=runs, full=True
        )
        _report(study, out, formats, f"map{suffix}")
        _print(map_lines(study))
    for suffix, damper in dampers:
        Omega, beta = grid_from("Omega", SPECTRUM_OMEGA), grid_from("beta", SPECTRUM_BETA)
        study = minimum_overturning_spectrum(setting, damper, Omega, beta, execution, runs=runs, **_tol(args))
        _report(study, out, formats, f"spectrum{suffix}")
        _print(spectrum_lines(study))
    _vertical_spectra(setting, replace(tuning, stops=True), execution, out, runs, formats, **_tol(args))
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
    _report(study, out, formats)
    _print(design_lines(study))
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
    _report(study, out, formats)
    _print(threshold_map_lines(study))
    print(
        f"demo: done in {time.perf_counter() - start:.0f} s; figures in {out}/ (map, map-unlimited, spectrum, "
        "spectrum-unlimited, spectrum-vertical, design, threshold .png/.pdf)"
    )
    return 0


def _vertical_spectra(
    setting: Setting, damper: Tuning, execution: Execution, out: Path, runs: Path, formats: tuple[str, ...], **tol
) -> None:
    """The demo's spectra of the block alone and with ``damper`` under pulses with the vertical ratios
    :data:`VERTICAL_RATIOS` (in phase), both directions, saved as ``spectrum-vertical-<ratio>`` (``0p5`` for 0.5)
    and drawn together as ``spectrum-vertical.png`` (and the other ``formats``)."""
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
    from ..plot.figures import draw_vertical_spectra

    paths = draw_vertical_spectra(studies, out, formats=formats)
    print(
        f"spectrum, vertical ratios {', '.join(f'{r:g}' for r in VERTICAL_RATIOS)}: wrote {', '.join(map(str, paths))}"
    )


def _cmd_redraw(args) -> int:
    formats = formats_from(args)
    preload(*STUDY_LIBRARIES)
    from ..plot.figures import redraw

    for path in args.paths:
        written = redraw(path, formats)
        print(f"redrew {', '.join(str(p) for p in written)}")
    return 0


#: Warnings of a study, and of implausible inputs, that the command line shows as one line each, like its errors.
STUDY_WARNINGS = (
    TileWarning,
    UndeterminedWarning,
    TMaxWarning,
    EdgeWarning,
    DesignWarning,
    PlausibilityWarning,
    FitWarning,
)


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


#: The long flag of each option of each study command (and demo, redraw) by its keyword: their errors name it.
FLAGS: dict[str, dict[str, str]] = {}


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
            print(f"rocking {args.command}: error: {named_as_flag(FLAGS[args.command], str(exc))}", file=sys.stderr)
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


def _described(text: str) -> str:
    """The description of a study command with the block options: its help, and where its block comes from."""
    return f"{text[:1].upper()}{text[1:]}. {block_help()}"


def _study_parser(subparsers, name: str, text: str) -> argparse.ArgumentParser:
    """A study's parser, its description saying which block it uses; the block options first."""
    p = add_parser(subparsers, name, text, _described(text))
    add_block_options(p)
    return p


def add_study_commands(subparsers) -> None:
    """Add one command per kind of :data:`rocking.study.kinds.KINDS`, built from its entry, then ``demo`` and
    ``redraw`` (the command line's own) to the ``rocking`` subparsers."""
    for name, kind in KINDS.items():
        command = kind.command
        blocks = any(group == "block" for group, _ in command.options)
        # A command with the block options says in its description where its block comes from.
        description = command.description or (_described(command.help) if blocks else None)
        p = add_parser(subparsers, name, command.help, description)
        for group, params in command.options:
            GROUPS[group].add(p, params, kind)
        p.set_defaults(func=_guarded(partial(run_study, name)))
        FLAGS[name] = flags_of(p)

    p = _study_parser(
        subparsers,
        "demo",
        "the damper as built: maps and spectra with stops and unlimited, both directions; design; Omega*",
    )
    _add_damper(p, tuned=True, searched=False, stops=False)
    _add_tol(p)
    _add_solver(p)
    p.set_defaults(func=_guarded(_cmd_demo))
    FLAGS["demo"] = flags_of(p)

    p = add_parser(subparsers, "redraw", "redraw figures from saved study data, without recomputing")
    p.add_argument("paths", nargs="+", help="a saved study (.nc, .json or their stem) or a folder of them")
    _add_formats(p)
    p.set_defaults(func=_guarded(_cmd_redraw))
    FLAGS["redraw"] = flags_of(p)
