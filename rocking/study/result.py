"""A finished study: its labelled data, its configuration, its summary and how it ran.

:mod:`rocking.study.storage` writes and reads it; :mod:`rocking.study.dataset` labels it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from .dataset import html, to_dataframes, to_dataset


@dataclass
class Study:
    """A finished study.

    Attributes
    ----------
    kind : str
        A kind of :data:`rocking.study.kinds.KINDS` (``"map"``, ``"spectrum"``, ...).
    config : dict
        Full JSON-ready configuration.
    arrays : dict of ndarray
        Every result array (what the figures are drawn from).
    summary : dict
        JSON-ready key results.
    run : dict
        How it ran (tiles computed and reused, wall time); not part of the configuration.
    tabulate : callable
        ``tabulate(arrays, config)``: its kind's tables (:attr:`tables`), the one place they are made,
        for a finished study and for one read back alike.
    """

    kind: str
    config: dict
    arrays: dict
    summary: dict = field(default_factory=dict)
    run: dict = field(default_factory=dict)
    tabulate: Callable[[dict, dict], dict] = field(default=lambda arrays, config: {}, repr=False, compare=False)

    @property
    def tables(self) -> dict:
        """CSV tables by file stem, each a dict of equal-length columns, made from its arrays."""
        return self.tabulate(self.arrays, self.config)

    def to_dataset(self):
        """The study as a labelled :class:`xarray.Dataset` (:func:`rocking.study.dataset.to_dataset`)."""
        return to_dataset(self)

    def to_dataframes(self) -> dict:
        """Its tables as :class:`pandas.DataFrame`, with units (:func:`rocking.study.dataset.to_dataframes`)."""
        return to_dataframes(self)

    def _repr_html_(self) -> str:
        return html(self)
