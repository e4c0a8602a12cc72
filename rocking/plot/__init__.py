"""Figures of the studies (:mod:`.figures`) and of responses (:mod:`.response`), drawn with matplotlib.

This module imports no matplotlib: the command line's parser reads the figures' formats here, and a command
that draws nothing (``rocking --help``, ``rocking simulate`` without ``--plot``) never loads it.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..model.params import ParameterError

#: The formats a study's figure is written in, each by matplotlib's Agg canvas from one layout ...
FORMATS = ("png", "pdf", "svg")
#: ... and those written unless others are asked for: a PDF costs about as much CPU as drawing the figure again.
DEFAULT_FORMATS = ("png",)


def check_formats(formats: Iterable[str], name: str = "formats") -> tuple[str, ...]:
    """The figure formats ``formats`` (lower case, each once, in the order given), or a ParameterError naming
    ``name`` and the formats of :data:`FORMATS`."""
    chosen = tuple(dict.fromkeys(str(f).strip().lower() for f in formats))
    unknown = [f for f in chosen if f not in FORMATS]
    if unknown or not chosen:
        raise ParameterError(
            f"{name} must be one or more of {', '.join(FORMATS)}, comma-separated (got {', '.join(unknown) or 'none'})"
        )
    return chosen
