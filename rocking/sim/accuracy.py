"""The tolerance check: is a response's answer a property of the block, or of the integrator's tolerance?

Rocking under a long excitation is sensitive to small perturbations (Yim, Chopra and Penzien
1980): a hundred impacts or more, each a small error of the integrator carried on, can end in
another response. Two runs at two tolerances can then agree by chance (both overturn, or both
reach the same ``theta_max`` by different paths), so one comparison is not enough: the check
(:func:`tolerance_check`) walks down a ladder of tolerances, each rung run twice (as given and
with the ground motion scaled by ``1 + PERTURBATION``), and stops early only where a rung follows
the trajectory of the one above it (the same events, the same maxima to :data:`SAME_FRACTION`).
A response is *sensitive* where the runs it made disagree (docs/simulation.md, "Sensitivity to
the tolerance"); it then carries their spread.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ..model.checks import RANGES, ParameterError
from ..model.motion import describe
from .boundary import CHECKED as CHECKED  # the results the check adds: declared with the others
from .boundary import SENSITIVE as SENSITIVE

#: The values of ``check``: ``"none"`` runs once; ``"tolerance"`` runs :func:`tolerance_check`.
CHECKS = ("none", "tolerance")

#: Each rung of the ladder is ``TIGHTEN`` times tighter than the one above it: two decades, well
#: past the spread of answers between neighbouring tolerances of a response that is not sensitive.
TIGHTEN = 100.0

#: The first rung below ``rtol`` is at most this. A record's steps are bounded by its sample spacing:
#: at looser tolerances the error control may never bind, so that runs at 1e-6, 1e-7 and 1e-8 take
#: the same steps and share one error (2 of 2,543 held-out responses of ``bench/sensitivity.py`` at
#: rtol 1e-6, first rung 1e-8: the answer moved only from 1e-9 on); the ladder would not see it
#: (docs/simulation.md, "Sensitivity to the tolerance").
FIRST_RUNG = 1e-10

#: The smallest valid ``rtol``: the ladder's last rung.
RTOL_MIN = RANGES["rtol"].low

#: Largest relative difference of ``theta_max`` or ``x_max`` between a run of the check and the
#: response it reports, for a response that is not sensitive, against the larger of the two. 10 %:
#: what a design reads off a response (a rotation over the slenderness angle, a stroke against a
#: half-width) is not read to better than that, and the spread of a sensitive response is far larger.
SENSITIVE_FRACTION = 0.10

#: Two runs follow one trajectory where they end alike (:data:`TRAJECTORY`) and their :data:`CLOSE`
#: results differ by at most this fraction: far closer than two runs that met by chance; only then
#: does the ladder stop early. Chosen on responses 0-2999 of ``bench/sensitivity.py``: 1e-3 without
#: ``t_end`` missed 3 answers at rtol 1e-6 (runs at 1e-6 and 1e-8 overturned 2 % apart in time, or
#: agreed to 5.5e-4 and both were wrong), 3e-4 with ``t_end`` none; 1e-4 leaves a margin for a few
#: more runs (4.06 a response on average at 1e-8, against 3.99).
SAME_FRACTION = 1e-4

#: Relative change of the ground motion's amplitude in the second run of each rung: far below any
#: record's precision, so that a response which moves with it is chaotic, not mistaken.
PERTURBATION = 1e-9

#: Runs added at the last rung, the motion scaled by ``1 + k PERTURBATION`` for ``k = 2, 3, ...``, where its two
#: runs disagree: the response is chaotic, and its spread is all there is to say of it.
SPREAD_RUNS = 6

#: What two runs of one trajectory share exactly: the verdict, how the run ended and its count of impacts.
TRAJECTORY = ("overturned", "status", "impacts")

#: What two runs of one trajectory share to :data:`SAME_FRACTION`: the maxima and when the run ended.
CLOSE = ("theta_max", "x_max", "t_end")

#: The results :func:`tolerance_check` reads of each run.
READ = (*TRAJECTORY, *CLOSE)


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
    """The next rung below ``rtol``: ``rtol / TIGHTEN``, floored at :data:`RTOL_MIN`."""
    return max(rtol / TIGHTEN, RTOL_MIN)


def ladder(rtol: float) -> tuple[float, ...]:
    """The tolerances of the check: ``rtol``, then from ``rtol / TIGHTEN`` (at most :data:`FIRST_RUNG`) each
    :func:`tighter_rtol` down to :data:`RTOL_MIN`."""
    rungs = [rtol]
    rung = max(min(rtol / TIGHTEN, FIRST_RUNG), RTOL_MIN)
    while rung < rungs[-1]:
        rungs.append(rung)
        rung = tighter_rtol(rung)
    return tuple(rungs)


def _apart(a, b, fraction: float) -> np.ndarray:
    """Elementwise: ``a`` and ``b`` differ by more than ``fraction`` of the larger of the two."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return np.abs(a - b) > fraction * np.maximum(np.abs(a), np.abs(b))


def sensitive(loose: Mapping, tight: Mapping):
    """Whether two runs of the same responses disagree: elementwise over arrays, or one bool.

    Parameters
    ----------
    loose, tight : mapping
        ``overturned``, ``theta_max`` [rad] and ``x_max`` [m] of two runs: numbers, or arrays of the
        same shape.

    Returns
    -------
    bool or ndarray of bool
        The verdict changed, or ``theta_max`` or ``x_max`` differ by more than
        :data:`SENSITIVE_FRACTION` of the larger of the two.
    """
    out = np.asarray(loose["overturned"], dtype=bool) != np.asarray(tight["overturned"], dtype=bool)
    for name in ("theta_max", "x_max"):
        out = out | _apart(loose[name], tight[name], SENSITIVE_FRACTION)
    return bool(out) if out.ndim == 0 else out


def same_trajectory(a: Mapping, b: Mapping) -> np.ndarray:
    """Elementwise: two runs end alike (:data:`TRAJECTORY`) with :data:`CLOSE` within :data:`SAME_FRACTION`."""
    out = np.ones(np.shape(a["theta_max"]), bool)
    for name in TRAJECTORY:
        out = out & (np.asarray(a[name]) == np.asarray(b[name]))
    for name in CLOSE:
        out = out & ~_apart(a[name], b[name], SAME_FRACTION)
    return out


@dataclass(frozen=True)
class Ladder:
    """What :func:`tolerance_check` ran and found.

    Attributes
    ----------
    runs : list of mapping
        What ``run_at`` gave, in the order run: the run at ``rtol`` first, then two a rung.
    counted : ndarray of bool, shape (len(runs), *shape)
        Which runs count for each response: those of the rungs it was open at.
    tightest : ndarray of int
        Each response's tightest run as given (an index into ``runs``).
    results : dict of ndarray
        :data:`CHECKED` by name: ``sensitive`` (a run it counts differs from its tightest, by
        :func:`sensitive`), ``theta_max_low`` and ``theta_max_high`` (the extremes of its runs'
        ``theta_max``), ``overturned_fraction`` (of its runs) and ``check_runs`` (their number).
    """

    runs: list
    counted: np.ndarray
    tightest: np.ndarray
    results: dict

    @property
    def reported(self) -> np.ndarray:
        """The run each response reports: its tightest where sensitive, else the run at the tolerance asked for."""
        return np.where(self.results[SENSITIVE.name], self.tightest, 0)


def tolerance_check(run_at: Callable[[float, float], Mapping], rtol: float) -> Ladder:
    """Run responses down the ladder of tolerances until each follows one trajectory, and say which moved.

    The run at ``rtol`` comes first. Each rung below it (:func:`ladder`) runs every response still
    open twice, as given and with the ground motion scaled by ``1 + PERTURBATION``; a response is
    closed where both follow the trajectory of its tightest run so far (:func:`same_trajectory`),
    and stays open to the last rung otherwise. Two runs that agree by chance (both overturned, or
    the same ``theta_max`` by other paths) do not close it: their events or their maxima differ.
    Where the last rung's two runs disagree (:func:`sensitive`), :data:`SPREAD_RUNS` more runs there
    sample the spread of a chaotic response.

    Parameters
    ----------
    run_at : callable
        ``run_at(rtol, factor)``: the results (:data:`READ` and any others;
        arrays of one shape, or numbers) of every response at ``rtol`` with the ground motion's
        amplitude scaled by ``factor``.
    rtol : float
        The tolerance asked for.

    Returns
    -------
    Ladder
    """
    runs = [run_at(rtol, 1.0)]
    shape = np.shape(runs[0]["theta_max"])
    counted = [np.ones(shape, bool)]
    tightest = np.zeros(shape, int)
    above = {k: np.asarray(runs[0][k]) for k in READ}  # each response's tightest run so far
    open_ = np.ones(shape, bool)
    for rung in ladder(rtol)[1:]:
        if not open_.any():
            break
        pair = [run_at(rung, 1.0), run_at(rung, 1.0 + PERTURBATION)]
        runs += pair
        counted += [open_, open_]
        tightest = np.where(open_, len(runs) - 2, tightest)
        closed = same_trajectory(above, pair[0]) & same_trajectory(above, pair[1])
        above = {k: np.where(open_, pair[0][k], v) for k, v in above.items()}
        open_ = open_ & ~closed
    if len(runs) > 1 and open_.any():
        # Down to the floor, and its own two runs disagree: chaotic. More samples of its input's neighbourhood.
        chaotic = open_ & np.asarray(sensitive(runs[-2], runs[-1]), bool)
        for k in range(2, 2 + SPREAD_RUNS) if chaotic.any() else ():
            runs.append(run_at(ladder(rtol)[-1], 1.0 + k * PERTURBATION))
            counted.append(chaotic)
    mask = np.stack(counted)
    theta = np.stack([np.broadcast_to(np.asarray(r["theta_max"], float), shape) for r in runs])
    over = np.stack([np.broadcast_to(np.asarray(r["overturned"], bool), shape) for r in runs])
    moved = np.stack([np.broadcast_to(np.asarray(sensitive(r, above), bool), shape) for r in runs])
    results = {
        SENSITIVE.name: (mask & moved).any(axis=0),
        "theta_max_low": np.where(mask, theta, np.inf).min(axis=0),
        "theta_max_high": np.where(mask, theta, -np.inf).max(axis=0),
        "overturned_fraction": (mask & over).sum(axis=0) / mask.sum(axis=0),
        "check_runs": mask.sum(axis=0),
    }
    return Ladder(runs, mask, tightest, results)


def _pick(runs: list, index: np.ndarray, name: str) -> np.ndarray:
    """Elementwise ``runs[index][name]``."""
    values = np.stack([np.broadcast_to(np.asarray(r[name]), index.shape) for r in runs])
    return np.take_along_axis(values, index[None], axis=0)[0]


def checked_fields(run_at: Callable[[float, float], Mapping], rtol: float) -> dict:
    """The results of a batch under the tolerance check: each response's run at ``rtol``, or where it is
    sensitive its tightest run as given, with :data:`CHECKED`.

    Parameters
    ----------
    run_at : callable
        As for :func:`tolerance_check`: ``run_at(rtol, factor)`` gives a dict of arrays of one shape.
    rtol : float
        The tolerance asked for.

    Returns
    -------
    dict of ndarray
        Every field of ``run_at``'s results, then :data:`CHECKED` by name.
    """
    done = tolerance_check(run_at, rtol)
    return {**{k: _pick(done.runs, done.reported, k) for k in done.runs[0]}, **done.results}
