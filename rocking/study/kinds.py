"""The kinds of study, one entry each: what runs it, what its saved data hold, its tables and its figure.

A new kind of study is its module (its driver, its tables) and one entry of :data:`KINDS`. The registry is
the top of :mod:`rocking.study`: it imports the kinds' modules, and none of them imports it
(:mod:`rocking.study.storage` reads a saved study through it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from . import design, ida, optimize, overturning_map, spectrum, threshold


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
    """

    driver: Callable
    grids: dict
    tables: Callable[[object, dict], dict]
    figure: str
    dims: Callable[[str], tuple]


#: Every kind of study, by the name its configuration and its saved files give it. ``grids``: the
#: configuration's grids, each with the dimension of its values.
KINDS = {
    "map": Kind(
        overturning_map.overturning_map,
        {"Omega": "Omega", "beta": "beta"},
        overturning_map.map_tables,
        "map_figure",
        overturning_map.DIMS.__getitem__,
    ),
    "spectrum": Kind(
        spectrum.minimum_overturning_spectrum,
        {"Omega": "Omega", "beta": "beta_scan"},
        spectrum.spectrum_tables,
        "spectrum_figure",
        spectrum.DIMS.__getitem__,
    ),
    "optimize": Kind(
        optimize.optimal_damper,
        {"Omega": "Omega", "Tm_ratio": "r_coarse"},
        optimize.optimize_tables,
        "optimize_figure",
        optimize.DIMS.__getitem__,
    ),
    "design": Kind(
        design.design,
        {"Omega": "Omega", "Tm_ratio": "r_coarse", "zeta_grid": "zeta_coarse"},
        design.design_tables,
        "design_figure",
        design.DIMS.__getitem__,
    ),
    "threshold": Kind(
        threshold.threshold_map,
        {"lam": "lam", "p": "p", "Omega": "Omega", "Tm_ratio": "r_coarse"},
        threshold.threshold_tables,
        "threshold_figure",
        threshold.DIMS.__getitem__,
    ),
    "ida": Kind(ida.incremental_dynamic_analysis, {"levels": "level"}, ida.tables, "ida_figure", ida.DIMS.__getitem__),
    "fragility": Kind(
        ida.incremental_dynamic_analysis, {"levels": "level"}, ida.tables, "ida_figure", ida.DIMS.__getitem__
    ),
}
