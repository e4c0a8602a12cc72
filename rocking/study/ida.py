"""Incremental dynamic analysis and fragility curves over a suite of ground motions, with and without the damper.

Every motion of a :class:`~rocking.study.suite.Suite` is scaled to every level of a grid,
either of its scale factor (``measure="scale"``: an incremental dynamic analysis) or of an
intensity measure (``"pga"``, ``"pgv"``, ``"arias"``, ``"cav"``,
:mod:`rocking.model.intensity`, or ``"amplitude"``, the ``a_g`` of a suite of pulses; each
motion scaled so that its measure equals the level: linear in the scale, quadratic for the
Arias intensity), in both directions
(:mod:`rocking.study.directions`), for the block alone and with the damper. One tile is one
motion of one part: the motion is made in the tile (:meth:`Suite.motion`), so memory does
not grow with the suite.

The outcome of a motion at a level is the envelope over the directions. The study reports
what the analysis shows, non-monotone outcomes included (a motion that overturns the block
at one level and not at a higher one: a "resurrection", :func:`~rocking.study.fragility.ida_summary`),
and the lognormal fragility fitted to all the stripes by maximum likelihood with its
bootstrap band (:mod:`rocking.study.fragility`).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..model.intensity import MEASURES, measure
from ..model.motion import SampledMotion, describe
from ..model.params import ParameterError
from ..sim.accuracy import SENSITIVE, check_choice, merged, tighter_rtol
from ..sim.cases import pulse_cases, run_cases, sampled_cases
from .config import Grid, Setting, Study, Tuning, Variant, part_config
from .directions import choose, response_envelope
from .fragility import FITTED, bootstrap_band, fit_lognormal, fragility_curve, ida_summary
from .overturning_map import FIELDS, check_damper, check_study, preflight, undetermined, warn_undetermined
from .suite import Suite, motion_names
from .tiles import LOCAL, Execution, Task, interleave, run_folder, run_tiles

#: What the levels of a study are: the scale factor itself, one of the intensity measures, or the
#: amplitude ``a_g`` of the pulses of a suite of pulses (the peak, but for the MP pulse's ``A omega_g``).
LEVELS = {"scale": "", **MEASURES, "amplitude": "m/s^2"}
#: Samples of an analytic pulse over its duration for its intensity measures (relative error below 1e-7).
PULSE_SAMPLES = 20_001
#: Points of the fitted curve and its band, and bootstrap resamples.
CURVE_POINTS, RESAMPLES = 101, 400


def scales_for(level, value: float, name: str) -> np.ndarray:
    """Scale factors that bring a motion whose measure ``name`` is ``value`` to each ``level``."""
    level = np.asarray(level, float)
    if name == "scale":
        return level
    if not value > 0:
        raise ParameterError(f"a motion whose {name} is {value!r} cannot be scaled to a level of {name}")
    return np.sqrt(level / value) if name == "arias" else level / value


def motion_measure(motion, name: str) -> float:
    """The measure ``name`` of a motion of a suite: 1 for ``"scale"``; the ``a_g`` of a pulse for
    ``"amplitude"``; otherwise :func:`rocking.model.intensity.measure` of its samples (of a pulse,
    :data:`PULSE_SAMPLES` of them over its duration)."""
    if name == "scale":
        return 1.0
    if isinstance(motion, SampledMotion):
        if name == "amplitude":
            raise ParameterError("measure 'amplitude' is the a_g of a suite of pulses: records have pga")
        return measure(name, motion.a, motion.dt)
    if name == "amplitude":
        return motion.a_g
    t = np.linspace(0.0, motion.t_p, PULSE_SAMPLES)
    return measure(name, motion.acceleration(t), t[1])  # every measure is blind to the sign


def _cases(setting: Setting, motion, scales: np.ndarray, signs, damper: dict):
    """The cases of ``motion`` (sampled or a pulse) at ``scales`` (rows) in the directions ``signs`` (columns)."""
    common = {"rtol": setting.rtol, "t_after": setting.t_after, **damper}
    signs = np.asarray(signs)[None, :]
    if isinstance(motion, SampledMotion):
        return sampled_cases(setting.block, motion, scales[:, None], sign=signs, **common)
    d, block = describe(motion), setting.block
    shape = {"psi": d.phase} if d.family == "sine" else {"gamma_mp": d.shape, "nu": d.phase} if d.family == "mp" else {}
    return pulse_cases(
        block,
        d.omega_g / block.p,
        motion.beta(block) * scales[:, None],
        sign=motion.sign * signs,
        motion=d.family,
        **shape,
        **common,
    )


def ida_tile(payload: tuple) -> dict:
    """One motion of one part at every level and direction: arrays ``(levels, signs)`` of the map's
    :data:`~rocking.study.overturning_map.FIELDS` and ``sensitive``, and ``im`` (1,): the motion's measure
    (:func:`motion_measure`).

    The responses are checked against a run at a tighter tolerance as ``check`` says
    (:func:`rocking.sim.accuracy.check_choice`: by default a sampled motion's, not a pulse's;
    ``sensitive`` marks those that moved, which hold the tighter run's results).

    ``payload = (setting, damper_or_None, suite, i, levels, name, signs, check)``.
    """
    setting, damper, suite, i, levels, name, signs, check = payload
    motion = suite.motion(i)
    value = motion_measure(motion, name)
    scales = scales_for(levels, value, name)
    result = run_cases(_cases(setting, motion, scales, signs, damper or {}), backend=setting.backend, threads=1)
    result = {k: result[k] for k in FIELDS}
    tight_rtol = tighter_rtol(setting.rtol)
    if check_choice(check, motion) == "tolerance" and tight_rtol != setting.rtol:
        tight = _cases(replace(setting, rtol=tight_rtol), motion, scales, signs, damper or {})
        result = merged(result, run_cases(tight, backend=setting.backend, threads=1))
    else:
        result[SENSITIVE.name] = np.zeros(len(levels) * len(signs), dtype=bool)
    shape = (len(levels), len(signs))
    return {**{k: v.reshape(shape) for k, v in result.items()}, "im": np.array([value])}


def _damper_args(tuning: Tuning | Variant) -> dict:
    """Keyword arguments of :func:`rocking.sim.cases.sampled_cases` for the study's damper."""
    return tuning.case_args()


def incremental_dynamic_analysis(
    setting: Setting,
    tuning: Tuning | Variant,
    suite: Suite,
    levels: Grid,
    execution: Execution = LOCAL,
    *,
    measure_name: str = "scale",
    directions: str = "auto",
    runs: str | Path = "out/runs",
    on_tile=None,
    check: str | None = None,
) -> Study:
    """Every motion of ``suite`` at every level, with and without the damper; the fragility fitted to it.

    Parameters
    ----------
    setting : Setting
        Block and solver.
    tuning : Tuning or Variant
        The damper.
    suite : Suite
        The motions.
    levels : Grid
        Scale factors (``measure_name="scale"``) or levels of the intensity measure, SI units.
    execution : Execution
        Where the tiles run.
    measure_name : {"scale", "pga", "pgv", "arias", "cav", "amplitude"}
        What the levels are (``"amplitude"``: suites of pulses only).
    directions : {"auto", "both", "positive", "negative"}
        Signs of the motions (:func:`rocking.study.directions.choose`).
    runs : path
        Folder of the run folders.
    on_tile : callable, optional
        Passed to :func:`rocking.study.tiles.run_tiles`.
    check : {"tolerance", "none"}, optional
        The tolerance check of every response, as :func:`rocking.simulate`'s: by default
        ``"tolerance"`` for a record or a stochastic motion, ``"none"`` for a pulse.

    Returns
    -------
    Study
        ``kind = "ida"`` (scale factors) or ``"fragility"`` (an intensity measure). Arrays ``levels``,
        ``signs``, ``im`` (each motion's measure), and per part ``bare``/``damper``: the map's fields per
        motion, level and direction (``<part>_<field>_by_sign``, (n, m, signs)), their envelope
        (``<part>_<field>``, (n, m)), the IDA summary (``<part>_first``, ``<part>_last_safe``,
        ``<part>_reversals``), the fraction overturned per level, ``<part>_sensitive_by_sign`` and
        ``<part>_sensitive`` (a response, or one of its directions, sensitive to the tolerance: as ``check``
        says, docs/simulation.md "Sensitivity to the tolerance"), the fraction
        of the responses sensitive per level (``<part>_sensitive_fraction``), the fitted curve ``<part>_curve`` at
        ``curve_x`` with its band ``<part>_band_low``/``_high`` (covering either answer of a sensitive response,
        :func:`~rocking.study.fragility.bootstrap_band`). The summary gives each part's fit
        (``theta``, ``beta`` and their intervals), the motions with resurrections and the number of sensitive
        responses.
    """
    check_study(setting, execution, runs, levels=levels)
    check_damper(tuning)
    if not isinstance(suite, Suite):
        raise ParameterError(f"suite must be a rocking.study.suite.Suite (got {type(suite).__name__})")
    if measure_name not in LEVELS:
        raise ParameterError(f"measure must be one of {', '.join(LEVELS)} (got {measure_name!r})")
    if measure_name == "amplitude" and not suite.pulses:
        raise ParameterError(
            "measure 'amplitude' is the a_g of a suite of pulses (Suite.from_pulses): records have pga"
        )
    if check is not None:
        check = check_choice(check, None)  # a value given is checked whatever the motion: refused before any run
    chosen = choose(directions, setting.block, tuning)
    signs = chosen["signs"]
    n, lv = len(suite), levels.values()
    grids = {
        "levels": levels.record(),
        "measure": measure_name,
        "signs": signs,
        "suite": suite.record(),
        "check": check,
    }
    arrays = {"levels": lv, "signs": np.array(signs), "im": np.full(n, np.nan)}
    groups, where, folders = [], {}, {}
    shape = (n, lv.size, len(signs))
    for part, damper, described in (("bare", None, None), ("damper", _damper_args(tuning), tuning.record())):
        for k in FIELDS:
            arrays[f"{part}_{k}_by_sign"] = np.zeros(
                shape, float if k in ("theta_max", "x_max", "bumper_force_max") else np.int64
            )
        arrays[f"{part}_sensitive_by_sign"] = np.zeros(shape, bool)
        folder = run_folder(runs, part_config("ida", part, setting, damper=described, **grids))
        folders[part] = folder.name
        tasks = []
        for i in range(n):
            payload = (setting, damper, suite, i, lv, measure_name, signs, check)
            expect = {**dict.fromkeys((*FIELDS, SENSITIVE.name), (lv.size, len(signs))), "im": (1,)}
            task = Task(folder / f"motion-{i}.npz", ida_tile, payload, expect)
            tasks.append(task)
            where[task.path] = (part, i)
        groups.append(tasks)

    def place(task: Task, tile: dict) -> None:
        part, i = where[task.path]
        for k in (*FIELDS, SENSITIVE.name):
            arrays[f"{part}_{k}_by_sign"][i] = tile[k]
        arrays["im"][i] = tile["im"][0]

    preflight(setting, tuning.case_args())
    stats = run_tiles(interleave(*groups), place, execution, backend=setting.backend, desc="ida", on_tile=on_tile)
    unknown = sum(int(undetermined(arrays[f"{p}_status_by_sign"]).sum()) for p in ("bare", "damper"))
    warn_undetermined("ida", unknown)
    positive = lv[lv > 0]
    arrays["curve_x"] = np.geomspace(positive.min(), positive.max(), CURVE_POINTS) if positive.size else lv
    summary = {
        "motions": n,
        "measure": measure_name,
        "unit": LEVELS[measure_name],
        "directions": chosen,
        "undetermined": unknown,
    }
    for part in ("bare", "damper"):
        by_sign = {k: arrays[f"{part}_{k}_by_sign"] for k in FIELDS}
        envelope = response_envelope(by_sign, undetermined(by_sign["status"]))
        arrays.update({f"{part}_{k}": envelope[k] for k in FIELDS})
        over = arrays[f"{part}_overturned"].astype(bool)
        ida = (
            ida_summary(lv, over)
            if lv.size > 1
            else {"first": np.full(n, np.nan), "last_safe": np.full(n, np.nan), "reversals": np.zeros(n, int)}
        )
        arrays.update({f"{part}_{k}": v for k, v in ida.items()})
        arrays[f"{part}_fraction"] = over.mean(axis=0)
        sensitive = arrays[f"{part}_sensitive_by_sign"]
        arrays[f"{part}_sensitive"] = sensitive.any(axis=-1)
        # Of the responses (motions and directions), not of the envelopes: each is one run that moved.
        arrays[f"{part}_sensitive_fraction"] = sensitive.mean(axis=(0, 2))
        uncertain = uncertain_verdicts(arrays[f"{part}_overturned_by_sign"], sensitive)
        summary[part] = _fit(lv, over, uncertain, arrays, part)
        summary[part]["motions_with_resurrections"] = int((ida["reversals"] > 0).sum())
        summary[part]["sensitive"] = int(sensitive.sum())
    kind = "ida" if measure_name == "scale" else "fragility"
    config = {"kind": kind, **setting.record(), "damper": tuning.record(), **grids, "directions": chosen}
    return Study(
        kind,
        config,
        arrays,
        tables=ida_tables(arrays, motion_names(grids["suite"]), kind),
        summary=summary,
        run={**stats.record(), "run_folders": folders, "responses": 2 * n * lv.size * len(signs)},
    )


def uncertain_verdicts(overturned_by_sign, sensitive_by_sign) -> np.ndarray:
    """The envelopes (over the directions, the last axis) whose verdict the tolerance can change.

    An envelope overturns if any direction does: a sensitive direction can change it unless a
    direction that is not sensitive overturns it for certain.
    """
    overturned, sensitive = np.asarray(overturned_by_sign, bool), np.asarray(sensitive_by_sign, bool)
    return sensitive.any(axis=-1) & ~(overturned & ~sensitive).any(axis=-1)


def _fit(levels, over, uncertain, arrays: dict, part: str) -> dict:
    """The lognormal fit of ``part`` and its band at ``arrays["curve_x"]`` (stored in ``arrays``), the band
    covering either verdict of the ``uncertain`` cells; the summary."""
    x = arrays["curve_x"]
    fit = (
        fit_lognormal(levels[levels > 0], over[:, levels > 0])
        if (levels > 0).sum() >= 2
        else {"theta": np.nan, "beta": np.nan, "log_likelihood": np.nan, "status": "too few levels"}
    )
    out = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in fit.items()}
    arrays[f"{part}_curve"] = np.full(x.size, np.nan)
    arrays[f"{part}_band_low"] = np.full(x.size, np.nan)
    arrays[f"{part}_band_high"] = np.full(x.size, np.nan)
    if fit["status"] in FITTED:
        arrays[f"{part}_curve"] = fragility_curve(x, fit["theta"], fit["beta"])
        fitted = levels > 0
        band = bootstrap_band(levels[fitted], over[:, fitted], x, sensitive=uncertain[:, fitted], resamples=RESAMPLES)
        arrays[f"{part}_band_low"], arrays[f"{part}_band_high"] = band["low"], band["high"]
        out.update(
            theta_interval=band["theta_interval"], beta_interval=band["beta_interval"], resamples=band["resamples"]
        )
    return out


def ida_tables(arrays: dict, names, kind: str) -> dict:
    """CSV tables: ``<kind>`` (one row per motion and level: the outcome of both parts) and ``<kind>-motions``
    (one row per motion: its measure and IDA summary)."""
    n, m = arrays["bare_overturned"].shape
    motion, level = np.meshgrid(np.arange(n), arrays["levels"], indexing="ij")
    rows = {"motion": motion.ravel(), "level": level.ravel()}
    for part in ("bare", "damper"):
        for k in ("overturned", "impacts", "theta_max", "x_max", "sensitive"):
            # A study saved before the tolerance check has no sensitive arrays: its table has no such column.
            if f"{part}_{k}" in arrays:
                rows[f"{part}_{k}"] = arrays[f"{part}_{k}"].ravel()
    motions = {"motion": np.arange(n), "name": np.array(names), "im": arrays["im"]}
    for part in ("bare", "damper"):
        for k in ("first", "last_safe", "reversals"):
            motions[f"{part}_{k}"] = arrays[f"{part}_{k}"]
    return {kind: rows, f"{kind}-motions": motions}
