"""The tolerance check: is a response's answer a property of the block, or of the integrator's tolerance?

Rocking under a long excitation is sensitive to small perturbations (Yim, Chopra and Penzien
1980): a hundred impacts or more, each a small error of the integrator carried on, can end in
another response. The check runs the response again at a tighter tolerance and calls it
*sensitive* where the two disagree (docs/simulation.md, "Sensitivity to the tolerance").
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..model.checks import RANGES, ParameterError
from ..model.motion import describe
from .boundary import SENSITIVE as SENSITIVE  # the result the check adds: declared with the others

#: The values of ``check``: ``"none"`` runs once; ``"tolerance"`` runs again at :func:`tighter_rtol`.
CHECKS = ("none", "tolerance")

#: The tighter run's tolerance is ``rtol / TIGHTEN``: two decades, well past the spread of
#: answers between neighbouring tolerances of a response that is not sensitive.
TIGHTEN = 100.0

#: The smallest valid ``rtol``.
RTOL_MIN = RANGES["rtol"].low

#: Largest relative difference of ``theta_max`` or ``x_max`` between the two runs of a response that is
#: not sensitive, against the larger of the two. 10 %: what a design reads off a response (a rotation
#: over the slenderness angle, a stroke against a half-width) is not read to better than that, and
#: the spread of answers between tolerances of a sensitive response is far larger (a factor of 4
#: on the case of docs/simulation.md).
SENSITIVE_FRACTION = 0.10

#: The results the check compares.
COMPARED = ("overturned", "theta_max", "x_max")


def check_choice(check: object, motion: object) -> str:
    """The check to run: ``check`` if given, else ``"tolerance"`` for a sampled motion, ``"none"`` for a pulse.

    Raises
    ------
    ParameterError
        ``check`` is neither ``None`` nor one of :data:`CHECKS` (one line naming the valid values).
    """
    if check is None:
        # Records and stochastic motions are long: many impacts, each carrying the integrator's
        # error on. A pulse's response is short and its studies are checked on their own grids.
        return "tolerance" if describe(motion).family == "sampled" else "none"
    if not isinstance(check, str) or check not in CHECKS:
        raise ParameterError(f"check must be one of {', '.join(CHECKS)} (got {check!r})")
    return check


def tighter_rtol(rtol: float) -> float:
    """The tolerance of the check's second run: ``rtol / TIGHTEN``, floored at :data:`RTOL_MIN`."""
    return max(rtol / TIGHTEN, RTOL_MIN)


def sensitive(loose: Mapping, tight: Mapping):
    """Whether two runs of the same responses disagree: elementwise over arrays, or one bool.

    Parameters
    ----------
    loose, tight : mapping
        ``overturned``, ``theta_max`` [rad] and ``x_max`` [m] of the runs at the tolerance asked for
        and at the tighter one: numbers, or arrays of the same shape.

    Returns
    -------
    bool or ndarray of bool
        The verdict changed, or ``theta_max`` or ``x_max`` differ by more than
        :data:`SENSITIVE_FRACTION` of the larger of the two.
    """
    out = np.asarray(loose["overturned"], dtype=bool) != np.asarray(tight["overturned"], dtype=bool)
    for name in ("theta_max", "x_max"):
        a, b = np.asarray(loose[name], dtype=float), np.asarray(tight[name], dtype=float)
        out = out | (np.abs(a - b) > SENSITIVE_FRACTION * np.maximum(np.abs(a), np.abs(b)))
    return bool(out) if out.ndim == 0 else out


def compared(response) -> dict:
    """The results of ``response`` that :func:`sensitive` compares, by name."""
    return {name: getattr(response, name) for name in COMPARED}


def merged(loose: Mapping, tight: Mapping) -> dict:
    """The results of a batch checked against its tighter run: the tighter run's where :func:`sensitive`.

    Parameters
    ----------
    loose, tight : mapping of ndarray
        The same fields (those of :data:`rocking.sim.problem.RESULT_FIELDS`, or any holding
        :data:`COMPARED`) of the same cases, at the tolerance asked for and at :func:`tighter_rtol`.

    Returns
    -------
    dict of ndarray
        Every field of ``loose``, each case's from the run it reports, and ``sensitive`` (bool).
    """
    flag = np.asarray(sensitive(loose, tight), dtype=bool)
    return {**{k: np.where(flag, tight[k], v) for k, v in loose.items()}, SENSITIVE.name: flag}
