"""The batches of a tile of several motions: their cases built at once, and the tolerance check run on the
responses it still counts.

A tile of an incremental dynamic analysis holds several motions of one part (:func:`rocking.study.ida.ida_tile`),
each at every level and direction. Each run the tile makes (the run at the tolerance asked for, then those of the
check's ladder, :func:`rocking.sim.accuracy.tolerance_check`) is one batch of all its motions' cases
(:func:`tile_cases`): the cases of one motion are built and checked by :func:`rocking.sim.cases.sampled_cases` (or
:func:`~rocking.sim.cases.pulse_cases`), and those of the other sampled motions are the same rows but for what a
motion gives its cases, not built and checked again a motion at a time. Each run below the first is made on the
responses the ladder still counts only (:func:`checked_rows`). A response's results do not depend on the batch it
runs in (rocking/sim/csrc/lanes.c: "each run's results do not depend on how a batch is cut"), so the tile's results
are those of its motions run one at a time.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..model.checks import RANGES
from ..model.loading import Model
from ..model.motion import SampledMotion, describe
from ..model.params import ParameterError
from ..sim.accuracy import checked_fields, tolerance_check
from ..sim.batch import Cases, Packed
from ..sim.cases import pulse_cases, sampled_cases
from .config import Setting


def motion_cases(setting: Setting, motion, scales: np.ndarray, signs, damper: dict) -> Cases:
    """The cases of ``motion`` (sampled or a pulse) at ``scales`` (rows) in the directions ``signs`` (columns)."""
    common = {"rtol": setting.rtol, "t_after": setting.t_after, **setting.floor_args(), **damper}
    signs = np.asarray(signs)[None, :]
    if isinstance(motion, SampledMotion):
        return sampled_cases(setting.block, motion, scales[:, None], sign=signs, **common)
    d, block = describe(motion), setting.block
    shape: dict[str, Any] = (
        {"psi": d.phase} if d.family == "sine" else {"gamma_mp": d.shape, "nu": d.phase} if d.family == "mp" else {}
    )
    return pulse_cases(
        block,
        d.omega_g / block.p,
        motion.beta(block) * scales[:, None],
        sign=motion.sign * signs,
        motion=d.family,
        **shape,
        **common,
    )


@dataclass(frozen=True)
class Rows:
    """The cases of a tile's motions, every level and direction, one row each, motion by motion: the settings of
    :class:`~rocking.sim.batch.Cases` not checked again until :meth:`take` makes a batch of some of them.

    Attributes
    ----------
    model : Model
    p : ndarray, shape (n, np)
    settings : dict
        Columns of ``n`` rows (``atol``: ``(n, ny)``), :class:`~rocking.sim.batch.Packed` for the series.
    """

    model: Model
    p: np.ndarray
    settings: dict

    def take(self, rows: np.ndarray) -> Cases:
        """The batch of the rows where ``rows`` (a mask) is True."""
        index = np.flatnonzero(rows)
        settings = {k: _rows(v, index) for k, v in self.settings.items()}
        return Cases(self.model, self.p[index], settings)


def _rows(column, index: np.ndarray):
    """The rows ``index`` of a setting (of a series: their offsets into the same values)."""
    return Packed(column.buffer, column.offset[index]) if isinstance(column, Packed) else column[index]


def _stacked(parts: Sequence[Cases]) -> Rows:
    """The cases of several motions built one at a time, as one :class:`Rows`."""
    settings: dict = {}
    for k, v in parts[0].settings.items():
        if isinstance(v, Packed):
            series = [part.settings[k] for part in parts]
            starts = np.cumsum([0] + [each.buffer.size for each in series[:-1]])
            offsets = np.concatenate([each.offset + start for each, start in zip(series, starts)])
            settings[k] = Packed(np.concatenate([each.buffer for each in series]), offsets)
        else:
            settings[k] = np.concatenate([part.settings[k] for part in parts])
    return Rows(parts[0].model, np.concatenate([part.p for part in parts]), settings)


def _plain(motions: Sequence) -> bool:
    """Whether every motion is sampled without a vertical component: then their cases differ only in what
    :func:`_motion_settings` sets."""
    return all(type(m) is SampledMotion and m.a_v is None for m in motions)


def _check_peaks(motions: Sequence[SampledMotion], scales: np.ndarray) -> None:
    """Refuse a motion whose peak at a scale is beyond the range of ``a_g``, as
    :func:`~rocking.sim.cases.sampled_cases` does for each motion."""
    valid, pga = RANGES["a_g"], np.array([m.pga for m in motions])
    bad = np.argwhere(~valid.holds(scales * pga[:, None]))
    if bad.size:
        i, j = bad[0]
        raw, peak = motions[i].pga / motions[i].scale, float(scales[i, j] * pga[i])
        raise ParameterError(
            f"scale max|a| (max|a| = {raw:g} m/s^2) gives a_g = {peak!r}, but a_g must be {valid.text()}: {valid.why}"
        )


def _tiled(column, count: int):
    """A setting of one motion's cases repeated for ``count`` motions (a series: its offsets, not its values)."""
    if isinstance(column, Packed):
        return Packed(column.buffer, np.tile(column.offset, count))
    return np.tile(column, (count,) + (1,) * (column.ndim - 1))


def tile_cases(setting: Setting, motions: Sequence, scales: np.ndarray, signs, damper: dict) -> Rows:
    """The cases of ``motions`` at their ``scales`` (one row per motion, one column per level) in the directions
    ``signs``: motion by motion, level by level, direction by direction.

    The first motion's cases are built and checked by :func:`motion_cases`. Those of the other motions, sampled
    without a vertical component, are its rows with the settings a motion gives them set as
    :func:`~rocking.sim.cases.sampled_cases` sets them (:func:`_motion_settings`); other motions (pulses, vertical
    components) are built one at a time.
    """
    if not _plain(motions):
        return _stacked([motion_cases(setting, m, s, signs, damper) for m, s in zip(motions, scales)])
    first = motion_cases(setting, motions[0], scales[0], signs, damper)
    _check_peaks(motions[1:], scales[1:])
    own = _motion_settings(motions, scales, signs, setting.t_after)
    settings = {k: own[k] if k in own else _tiled(v, len(motions)) for k, v in first.settings.items()}
    return Rows(first.model, np.tile(first.p, (len(motions), 1)), settings)


def _motion_settings(motions: Sequence[SampledMotion], scales: np.ndarray, signs, t_after: float) -> dict:
    """What each sampled motion gives its cases (:func:`~rocking.sim.cases.sampled_cases`), one row per case: its
    amplitude ``a_g`` at each scale and direction, the end of its record and of its runs, its samples and their
    spacing; every other setting is the same for every motion (``tests/test_batches.py`` holds them all against
    the cases of each motion built alone)."""
    per = scales.shape[1] * len(signs)
    sign = np.asarray(signs, dtype=np.int64)[None, :]
    a_g = [sign * m.sign * (m.scale * scale[:, None]) for m, scale in zip(motions, scales)]
    t_p = np.repeat(np.array([m.t_p for m in motions], dtype=float), per)
    samples = [m.a for m in motions]
    starts = np.cumsum([0] + [a.size for a in samples[:-1]]).astype(np.int64)
    return {
        "a_g": np.concatenate([a.ravel() for a in a_g]),
        "t_p": t_p,
        "t_max": t_p + t_after,
        "pulse_dt": np.repeat(np.array([m.dt for m in motions], dtype=float), per),
        "n_samples": np.repeat(np.array([m.n for m in motions], dtype=float), per),
        "samples": Packed(np.concatenate(samples).astype(float), np.repeat(starts, per)),
    }


def _placed(base: np.ndarray, rows: np.ndarray, values: np.ndarray) -> np.ndarray:
    """``base`` with ``values`` where the mask ``rows`` is True."""
    out = base.copy()
    out[rows] = values
    return out


class _NotRun(Exception):
    """The ladder asked for a run before any was made."""


def checked_rows(run: Callable[[float, float, np.ndarray], dict], rtol: float, n: int) -> dict:
    """:func:`rocking.sim.accuracy.checked_fields` of ``n`` responses, each run of the ladder made on the responses
    it counts only.

    The ladder is replayed on the runs made so far, a stand-in given for the next (any run: which responses a run
    counts is decided before it is made, from the runs above it); the next run is then made on the responses it
    counts (its ``counted``), the others holding the first run's results, which the ladder does not count there.
    After the last run, the ladder is replayed on the runs made.

    Parameters
    ----------
    run : callable
        ``run(rtol, factor, rows)``: the results (a dict of arrays, one value per True of ``rows``) of the
        responses where the mask ``rows`` (of ``n``) is True, at ``rtol`` with the ground motion's amplitude scaled
        by ``factor``.
    rtol : float
        The tolerance asked for.
    n : int
        The responses.

    Returns
    -------
    dict of ndarray
        As :func:`~rocking.sim.accuracy.checked_fields`.
    """
    made: list[dict] = []
    rows: list[np.ndarray] = []
    while True:
        counted, asked = _replay(made, rtol, n)
        for j in range(len(made)):
            if np.any(counted[j] & ~rows[j]):
                raise RuntimeError(f"the tolerance check counts a response of its run {j} that was not made")
        if len(asked) == len(made):
            break
        need = counted[len(made)]
        result = run(*asked[len(made)], need)
        made.append(result if not made else {k: _placed(made[0][k], need, v) for k, v in result.items()})
        rows.append(need)
    runs = iter(made)
    return checked_fields(lambda r, factor: next(runs), rtol)


def _replay(made: list[dict], rtol: float, n: int) -> tuple[np.ndarray, list[tuple[float, float]]]:
    """The ladder of :func:`~rocking.sim.accuracy.tolerance_check` replayed on the runs ``made``, a stand-in (the
    last run made) given for any other: which responses each run counts, and the ``(rtol, factor)`` of each run
    asked for. Before any run is made: every response counts in the first."""
    asked: list[tuple[float, float]] = []

    def replay(r: float, factor: float) -> dict:
        asked.append((r, factor))
        if len(asked) <= len(made):
            return made[len(asked) - 1]
        if not made:
            raise _NotRun
        return made[-1]

    try:
        return tolerance_check(replay, rtol).counted, asked
    except _NotRun:
        return np.ones((1, n), bool), asked
