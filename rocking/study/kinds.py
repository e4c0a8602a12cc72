"""The kinds of study, one entry each: what runs it, what its saved data hold, its tables, its figure and its command.

A new kind of study is its module (its driver, its tables) and one entry of :data:`KINDS`. The registry is
the top of :mod:`rocking.study`: it imports the kinds' modules, and none of them imports it
(:mod:`rocking.study.storage` reads a saved study through it). Its command is data here (:class:`Command`):
the ``rocking`` command (:mod:`rocking.cli.study`) builds one subcommand of each entry and runs it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from . import design, friction_map, ida, optimize, overturning_map, spectrum, threshold

#: Default grids (MIN, MAX, N) of the commands; docs/model.md section 9 gives the ranges. The beta
#: scans of spectra start at 0.5, below the uplift threshold (about 0.9 .. 1.1 for the reference
#: block), so that beta_min is bracketed also for long, quasi-static pulses.
MAP_OMEGA, MAP_BETA = (0.5, 15.0, 146), (1.0, 15.0, 141)
SPECTRUM_OMEGA, SPECTRUM_BETA = (0.5, 15.0, 59), (0.5, 15.0, 117)
OPTIMIZE_OMEGA, OPTIMIZE_BETA = (0.5, 15.0, 30), (0.5, 15.0, 59)
OPTIMIZE_GAMMAS = (0.02, 0.05, 0.1)
#: The band of pulses of ``design`` and its beta scan (reaching above the damped block's beta_min at Omega = 8).
DESIGN_OMEGA, DESIGN_BETA = (2.0, 8.0, 7), (0.5, 25.0, 50)
#: Default grids of the regime map over floors and amplitudes, and its pulses' frequency ratio: the issue-37 block
#: (H = 2 m, B = 0.5 m) under a one-sine pulse of T_g = 0.5 s has Omega = 4.7; mu spans Shenton's B/H = 0.25.
FRICTION_MU, FRICTION_BETA, FRICTION_OMEGA = (0.1, 0.6, 26), (0.4, 2.4, 26), 4.7
#: Default levels of ida (scale factors) and fragility (PGA, m/s^2).
IDA_SCALES, FRAGILITY_LEVELS = (0.25, 4.0, 16), (0.5, 10.0, 20)


@dataclass(frozen=True)
class Command:
    """The subcommand ``rocking KIND`` of a kind, as data; :mod:`rocking.cli.study` builds and runs it.

    Attributes
    ----------
    help : str
        Its one-line help (its description adds where its block comes from, with the block options).
    options : tuple
        Its option groups in order, each ``(name, params)``: ``name`` a group of the command line's table
        (:data:`rocking.cli.study.GROUPS`: ``"block"``, ``"damper"``, ``"grid"``, ``"solver"``, ...), ``params``
        a dict of what that group takes (a grid's ``name``, ``default`` (MIN, MAX, N) and ``help``, ...).
    inputs : tuple
        The positional arguments of its driver, by the names the groups give their values (``"setting"``: the
        :class:`~rocking.study.config.Setting` of the block, pulse and solver options); the others are keywords.
    function : str
        The public function of :mod:`rocking.study.api` that computes the same (each option is one of its
        keywords, tests/test_python_cli.py), by name: the API imports the kinds' modules as this does.
    describe : str
        The function of :mod:`rocking.cli.study` that gives its summary lines, ``describe(study) -> list[str]``.
    description : str, optional
        Its description, when it has no block options (which say where the block comes from).
    """

    help: str
    options: tuple
    inputs: tuple
    function: str
    describe: str
    description: str | None = None


@dataclass(frozen=True)
class Kind:
    """One kind of study.

    Attributes
    ----------
    driver : callable
        The function that runs it and returns its :class:`rocking.study.result.Study`.
    grids : dict
        The grids of its configuration (:meth:`rocking.study.config.Grid.record`), each with the array of
        its values in its data.
    tables : callable
        ``tables(data, config)``: its CSV tables by file stem, from its data
        (:attr:`rocking.study.result.Study.data`).
    figure : str
        The function of :mod:`rocking.plot.figures` that draws it (the plots are a layer above the studies).
    dims : callable
        ``dims(name)``: the dimensions of its data's variable ``name`` (a KeyError for a name it has none of).
    command : Command
        Its subcommand of ``rocking``.
    """

    driver: Callable
    grids: dict
    tables: Callable[[object, dict], dict]
    figure: str
    dims: Callable[[str], tuple]
    command: Command


def _grid(name: str, default: tuple, text: str, si: str | None = None) -> tuple:
    """A grid option; ``si``: the keyword of its alternative in SI units (``"T_g"`` for ``Omega``, ``"a_g"`` for
    ``beta``: :func:`rocking.study.config.pulse_grids`)."""
    return ("grid", {"name": name, "default": default, "help": text, **({"si": si} if si else {})})


#: The options every pulse study ends with, after its own.
_PULSE_STUDY: tuple[tuple[str, dict], ...] = (("directions", {}), ("pulse", {}), ("floor", {}), ("solver", {}))
#: Those of the maps and spectra, whose pulses may have a vertical component.
_VERTICAL_STUDY: tuple[tuple[str, dict], ...] = (
    ("directions", {}),
    ("pulse", {}),
    ("vertical", {}),
    ("floor", {}),
    ("solver", {}),
)
#: The options of the motions of ida and fragility, before their levels.
_MOTIONS: tuple[tuple[str, dict], ...] = (("block", {}), ("damper", {"tuned": True}), ("variant", {}), ("motions", {}))
#: The options of ida and fragility, after their levels.
_MOTIONS_END: tuple[tuple[str, dict], ...] = (("directions", {}), ("floor", {}), ("solver", {}), ("check", {}))
#: The positional arguments of the drivers of the studies of one damper, or of a model variant.
_ONE_DAMPER = ("setting", "damper", "Omega", "beta", "execution")
_MOTION_STUDY = ("setting", "damper", "suite", "levels", "execution")

#: Every kind of study, by the name its configuration and its saved files give it. ``grids``: the
#: configuration's grids, each with the dimension of its values.
KINDS = {
    "map": Kind(
        overturning_map.overturning_map,
        {"Omega": "Omega", "beta": "beta"},
        overturning_map.map_tables,
        "map_figure",
        overturning_map.DIMS.__getitem__,
        Command(
            "overturning map over (Omega, beta), block alone and with a damper",
            (
                ("block", {}),
                ("damper", {"tuned": True}),
                ("variant", {}),
                _grid("Omega", MAP_OMEGA, "pulse frequency ratios omega_g / p", "T_g"),
                _grid("beta", MAP_BETA, "pulse amplitude ratios a_g / (g tan alpha)", "a_g"),
                ("tile", {}),
                ("refinement", {}),
                *_VERTICAL_STUDY,
            ),
            _ONE_DAMPER,
            "overturning_map",
            "map_lines",
        ),
    ),
    "spectrum": Kind(
        spectrum.minimum_overturning_spectrum,
        {"Omega": "Omega", "beta": "beta_scan"},
        spectrum.spectrum_tables,
        "spectrum_figure",
        spectrum.DIMS.__getitem__,
        Command(
            "minimum overturning amplitude beta_min(Omega), with safe windows",
            (
                ("block", {}),
                ("damper", {"tuned": True}),
                ("variant", {}),
                _grid("Omega", SPECTRUM_OMEGA, "pulse frequency ratios", "T_g"),
                _grid("beta", SPECTRUM_BETA, "scan amplitudes (the step bounds the windows seen)", "a_g"),
                ("tol", {}),
                *_VERTICAL_STUDY,
            ),
            _ONE_DAMPER,
            "minimum_overturning_spectrum",
            "spectrum_lines",
        ),
    ),
    "optimize": Kind(
        optimize.optimal_damper,
        {"Omega": "Omega", "Tm_ratio": "r_coarse"},
        optimize.optimize_tables,
        "optimize_figure",
        optimize.DIMS.__getitem__,
        Command(
            "optimal damper period and best gain against Omega; threshold Omega*",
            (
                ("block", {}),
                ("damper", {"searched": True, "gammas": OPTIMIZE_GAMMAS}),
                _grid("Omega", OPTIMIZE_OMEGA, "pulse frequency ratios"),
                _grid("beta", OPTIMIZE_BETA, "scan amplitudes of every beta_min"),
                ("search", {"default": optimize.TM_GRID}),
                ("tol", {}),
                *_PULSE_STUDY,
            ),
            ("setting", "gammas", "Omega", "beta", "execution"),
            "optimal_damper",
            "threshold_lines",
        ),
    ),
    "design": Kind(
        design.design,
        {"Omega": "Omega", "Tm_ratio": "r_coarse", "zeta_grid": "zeta_coarse"},
        design.design_tables,
        "design_figure",
        design.DIMS.__getitem__,
        Command(
            "one damper with stops for a band of pulses: the best worst gain, in SI units",
            (
                ("block", {}),
                ("design damper", {"default": design.TM_GRID, "zeta_grid": design.ZETA_GRID}),
                _grid("Omega", DESIGN_OMEGA, "the band of pulse frequency ratios", "T_g"),
                _grid("beta", DESIGN_BETA, "scan amplitudes of every beta_min", "a_g"),
                ("tol", {}),
                *_PULSE_STUDY,
            ),
            ("setting", "Omega", "beta", "execution"),
            "design",
            "design_lines",
        ),
    ),
    "threshold": Kind(
        threshold.threshold_map,
        {"lam": "lam", "p": "p", "Omega": "Omega", "Tm_ratio": "r_coarse"},
        threshold.threshold_tables,
        "threshold_figure",
        threshold.DIMS.__getitem__,
        Command(
            "threshold frequency Omega* over block geometries, unlimited guide and stops",
            (
                _grid("lam", threshold.LAM_GRID, "slenderness H/B of the blocks"),
                _grid("p", threshold.P_GRID, "size p = sqrt(3 g / 4 R) of the blocks, rad/s"),
                _grid("Omega", threshold.OMEGA_GRID, "pulse frequency ratios scanned at each geometry"),
                ("threshold damper", {"default": threshold.TM_GRID}),
                ("tol", {}),
                ("directions", {}),
                ("solver", {}),
            ),
            ("lam", "p", "Omega", "execution"),
            "threshold_map",
            "threshold_map_lines",
            "The threshold frequency Omega* (above it the best damper gains less than 1 %) over a grid of "
            "slenderness lambda = H/B and size p, for the unlimited guide and the stops at the block's edges, both "
            "directions; the beta scan rises until the block overturns or the pulse passes --a-max g.",
        ),
    ),
    "friction": Kind(
        friction_map.friction_map,
        {"mu": "mu", "beta": "beta"},
        friction_map.friction_tables,
        "friction_figure",
        friction_map.DIMS.__getitem__,
        Command(
            "regime map over floors and amplitudes (mu, beta) at one Omega: rest, rocks, slides, slides and "
            "rocks, overturns",
            (
                ("block", {}),
                ("frequency", {"default": FRICTION_OMEGA}),
                _grid("mu", FRICTION_MU, "Coulomb friction of the floors, static = kinetic"),
                _grid("beta", FRICTION_BETA, "pulse amplitude ratios a_g / (g tan alpha)", "a_g"),
                ("directions", {}),
                ("pulse", {}),
                ("solver", {}),
            ),
            ("setting", "Omega", "mu", "beta", "execution"),
            "friction_map",
            "friction_lines",
        ),
    ),
    "ida": Kind(
        ida.incremental_dynamic_analysis,
        {"levels": "level"},
        ida.tables,
        "ida_figure",
        ida.DIMS.__getitem__,
        Command(
            "incremental dynamic analysis: every record at every scale factor, with and without the damper",
            (
                *_MOTIONS,
                (
                    "levels",
                    {
                        "name": "scales",
                        "default": IDA_SCALES,
                        "help": "scale factors of every record",
                        "measure": "scale",
                    },
                ),
                *_MOTIONS_END,
            ),
            _MOTION_STUDY,
            "incremental_dynamic_analysis",
            "fit_lines",
        ),
    ),
    "fragility": Kind(
        ida.incremental_dynamic_analysis,
        {"levels": "level"},
        ida.tables,
        "ida_figure",
        ida.DIMS.__getitem__,
        Command(
            "fragility curves: the probability of overturning against an intensity measure, "
            "over a suite of records or of stochastic motions",
            (
                *_MOTIONS,
                ("im", {}),
                (
                    "levels",
                    {
                        "name": "levels",
                        "default": FRAGILITY_LEVELS,
                        "help": "levels of the intensity measure, SI units (m/s2 for pga)",
                    },
                ),
                *_MOTIONS_END,
            ),
            _MOTION_STUDY,
            "fragility",
            "fit_lines",
        ),
    ),
}
