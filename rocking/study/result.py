"""A finished study: its labelled data, its configuration, its summary and how it ran.

:mod:`rocking.study.storage` writes and reads it; its figures (:mod:`rocking.plot.figures`) and its tables
read its data.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from .dataset import html, to_dataframes, to_dataset

if TYPE_CHECKING:  # xarray is imported where a study is made, not by import rocking
    import xarray as xr


@dataclass
class Study:
    """A finished study.

    Attributes
    ----------
    kind : str
        A kind of :data:`rocking.study.kinds.KINDS` (``"map"``, ``"spectrum"``, ...).
    config : dict
        Full JSON-ready configuration.
    data : xarray.Dataset
        Its results, labelled: dimensions named after the swept quantities, coordinates in non-dimensional
        and SI terms, units on every variable (:mod:`rocking.study.dataset`).
    summary : dict
        JSON-ready key results.
    run : dict
        How it ran (tiles computed and reused, wall time); not part of the configuration.
    tabulate : callable
        ``tabulate(data, config)``: its kind's tables (:attr:`tables`), the one place they are made, for a
        finished study and for one read back alike.
    """

    kind: str
    config: dict
    data: xr.Dataset
    summary: dict = field(default_factory=dict)
    run: dict = field(default_factory=dict)
    tabulate: Callable[[xr.Dataset, dict], dict] = field(default=lambda data, config: {}, repr=False, compare=False)

    @property
    def tables(self) -> dict:
        """CSV tables by file stem, each a dict of equal-length columns, made from its data."""
        return self.tabulate(self.data, self.config)

    def to_dataset(self, versions: dict | None = None):
        """Its data with its configuration, summary and versions as attributes (:func:`to_dataset`)."""
        return to_dataset(self, versions)

    def to_dataframes(self) -> dict:
        """Its tables as :class:`pandas.DataFrame`, with units (:func:`rocking.study.dataset.to_dataframes`)."""
        return to_dataframes(self)

    def _repr_html_(self) -> str:
        return html(self)
