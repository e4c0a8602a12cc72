"""The CSV tables of a study, made again from its arrays and configuration: a study read back has them.

A study computes its tables when it finishes; :func:`rocking.load` reads only the arrays and the
JSON record, and asks :func:`tables` for the same tables, so that
:meth:`~rocking.study.config.Study.to_dataframes` of a loaded study gives what the finished one gave.
"""

from __future__ import annotations

from ..model.params import Block
from .design import candidates_table, design_table
from .ida import ida_tables
from .optimize import optimize_table
from .overturning_map import half_stroke, map_table
from .spectrum import spectrum_tables
from .suite import motion_names
from .threshold import threshold_table


def _map(arrays: dict, config: dict) -> dict:
    block = Block(**config["block"])
    return {"map": map_table(arrays, block.B / 2, half_stroke(block, config["damper"]))}


#: Per kind: ``(arrays, config) -> {table name: columns}``.
TABLES = {
    "map": _map,
    "spectrum": lambda arrays, config: spectrum_tables(arrays),
    "optimize": lambda arrays, config: {"optimize": optimize_table(arrays)},
    "design": lambda arrays, config: {"design": design_table(arrays), "design-candidates": candidates_table(arrays)},
    "threshold": lambda arrays, config: {"threshold": threshold_table(arrays)},
    "ida": lambda arrays, config: ida_tables(arrays, motion_names(config["suite"]), "ida"),
    "fragility": lambda arrays, config: ida_tables(arrays, motion_names(config["suite"]), "fragility"),
}


def tables(kind: str, arrays: dict, config: dict) -> dict:
    """The tables of a study of ``kind`` (a key of :data:`TABLES`) with these arrays and configuration."""
    return TABLES[kind](arrays, config)
