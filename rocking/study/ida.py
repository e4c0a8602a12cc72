"""Incremental dynamic analysis and fragility curves over a suite of ground motions, with and without the damper.

Every motion of a :class:`~rocking.study.suite.Suite` is scaled to every level of a grid,
either of its scale factor (``measure="scale"``: an incremental dynamic analysis) or of an
intensity measure (``"pga"``, ``"pgv"``, ``"arias"``, ``"cav"``,
:mod:`rocking.model.intensity`, or ``"amplitude"``, the ``a_g`` of a suite of pulses; each
motion scaled so that its measure equals the level: linear in the scale, quadratic for the
Arias intensity), in both directions
(:mod:`rocking.study.directions`), for the block alone and with the damper. A tile is a few
motions of one part (:func:`tile_bounds`), each run of their responses one batch
(:mod:`rocking.study.batches`): the motions are made in the tile (:meth:`Suite.motion`), so
memory does not grow with the suite.

The outcome of a motion at a level is the envelope over the directions. The study reports
what the analysis shows, non-monotone outcomes included (a motion that overturns the block
at one level and not at a higher one: a "resurrection", :func:`~rocking.study.fragility.ida_summary`),
and the lognormal fragility fitted to all the stripes by maximum likelihood with its
bootstrap band (:mod:`rocking.study.fragility`).
"""

from __future__ import annotations

import os
import sys
import warnings
from dataclasses import replace
from pathlib import Path
from types import FrameType
from typing import Any

import numpy as np

from ..model.intensity import MEASURES, measure
from ..model.motion import SampledMotion
from ..model.params import ParameterError
from ..sim.accuracy import SENSITIVE, check_choice, tighter_rtol
from ..sim.cases import run_cases
from . import directions
from .batches import checked_rows, tile_cases
from .config import Grid, Setting, Tuning, Variant, part_config
from .dataset import coordinate_attrs, field_attrs
from .directions import choose, response_envelope
from .fragility import (
    FITTED,
    MEDIAN_PLACES,
    FitWarning,
    bootstrap_band,
    fit_lognormal,
    fit_warnings,
    fragility_curve,
    ida_summary,
    median_place,
    median_words,
)
from .overturning_map import (
    FIELDS,
    FLIGHT_FIELDS,
    PARTS,
    check_damper,
    check_study,
    preflight,
    reached_t_max,
    undetermined,
    warn_t_max,
    warn_undetermined,
)
from .result import Study
from .suite import Suite, motion_names, vertical_names
from .tiles import LOCAL, Execution, Task, interleave, run_folder, run_tiles
from .vocabulary import FIT_STATUSES, PART_NAMES

#: What the levels of a study are: the scale factor itself, one of the intensity measures, or the
#: amplitude ``a_g`` of the pulses of a suite of pulses (the peak, but for the MP pulse's ``A omega_g``).
LEVELS = {"scale": "", **MEASURES, "amplitude": "m/s^2"}
#: Samples of an analytic pulse over its duration for its intensity measures (relative error below 1e-7).
PULSE_SAMPLES = 20_001
#: Responses (motions x levels x directions) a tile runs at the tolerance asked for, about, at most
#: (:func:`tile_bounds`): enough that its own costs (building and checking its batches, replaying the tolerance
#: check, writing its file) are small beside its runs'.
TILE_RESPONSES = 512
#: Tiles a part is cut into at least, where it has the motions: work for several workers on a suite of a few
#: tens of motions.
MIN_TILES = 4
#: Points of the fitted curve and its band, and bootstrap resamples.
CURVE_POINTS, RESAMPLES = 101, 400

#: What the envelopes of an IDA give per part, besides the responses: per motion, per level, along the fitted curve.
RESULTS = (
    "first",
    "last_safe",
    "reversals",
    "sensitive_responses",
    "fraction",
    "sensitive_fraction",
    "curve",
    "band_low",
    "band_high",
)
#: The fitted lognormal of each part (NaN where the fit gives no curve) and the ends of its 90 % intervals.
FIT = ("median", "dispersion", "median_low", "median_high", "dispersion_low", "dispersion_high")
#: What else each part's fit and runs give, one value per part: the fit's outcome (a code of
#: :data:`~rocking.study.vocabulary.FIT_STATUSES`), where its median lies against the levels (a code of
#: :data:`~rocking.study.fragility.MEDIAN_PLACES`), its log-likelihood, its bootstrap's resamples, and the
#: responses without a verdict.
COUNTS = ("fit_status", "median_extrapolated", "log_likelihood", "resamples", "undetermined")
#: What the runs of a suite with a vertical component give per part beside :data:`COUNTS` (docs/model.md section
#: 16): the responses that flew and landed without overturning, and those that flew and overturned.
FLIGHT_COUNTS = ("flies_and_lands", "flies_and_overturns")
#: Units, meaning and key of the variables of an IDA that :data:`rocking.study.dataset.FIELDS` does not label.
OWN_FIELDS: dict[str, tuple] = {
    "fit_status": ("1", "outcome of the lognormal fit", dict(enumerate(FIT_STATUSES))),
    "median_extrapolated": (
        "1",
        "where the fitted median lies against the levels tested: within them, or extrapolated above the highest "
        "or below the lowest",
        dict(enumerate(MEDIAN_PLACES)),
    ),
    "log_likelihood": ("1", "binomial log-likelihood of the fitted lognormal, from the counts of every level"),
    "resamples": ("1", "bootstrap resamples of the motions fitted for the band and the intervals"),
    "sensitive_responses": (
        "1",
        "responses of the motion (levels and directions) sensitive to the tolerance; NaN: not checked",
    ),
    "flies_and_lands": ("1", "responses whose base left the floor and landed, to a verdict, without overturning"),
    "flies_and_overturns": ("1", "responses whose base left the floor and that overturned"),
}

#: The dimensions of every variable of an IDA's or a fragility's data (:func:`ida_data`), coordinates included.
DIMS = {
    **{dim: (dim,) for dim in ("part", "motion", "level", "sign", "curve_x")},
    "im": ("motion",),
    "vertical_motion": ("motion",),
    **dict.fromkeys((*FIELDS, *FLIGHT_FIELDS, SENSITIVE.name), ("part", "motion", "level", "sign")),
    **dict.fromkeys(("first", "last_safe", "reversals", "sensitive_responses"), ("part", "motion")),
    **dict.fromkeys(("fraction", "sensitive_fraction"), ("part", "level")),
    **dict.fromkeys((*FIT, *COUNTS, *FLIGHT_COUNTS), ("part",)),
    **dict.fromkeys(("curve", "band_low", "band_high"), ("part", "curve_x")),
}


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


def tolerance_checked(check: str | None, motion, rtol: float) -> bool:
    """Whether the responses to ``motion`` are run again at a tighter tolerance: ``check`` (or its default for the
    motion, :func:`rocking.sim.accuracy.check_choice`) is ``"tolerance"``, and a tighter tolerance than ``rtol``
    exists."""
    return check_choice(check, motion) == "tolerance" and tighter_rtol(rtol) != rtol


def ida_tile(payload: Any) -> dict:
    """Motions ``first`` to ``stop - 1`` of one part at every level and direction: arrays ``(motions, levels,
    signs)`` of the map's :data:`~rocking.study.overturning_map.FIELDS` and ``sensitive``, and ``im`` (motions,):
    each motion's measure (:func:`motion_measure`).

    Each run is one batch of every motion's cases (:func:`rocking.study.batches.tile_cases`). The responses are
    checked down the ladder of tolerances as ``check`` says (:func:`tolerance_checked`: by default a sampled
    motion's, not a pulse's; :func:`rocking.study.batches.checked_rows`, each run below the first made on the
    responses the ladder still counts; ``sensitive`` marks those whose runs disagree, which hold their tightest
    run's results; all False where no check ran, which the study then drops).

    ``payload = (setting, damper_or_None, suite, first, stop, levels, name, signs, check)``.
    """
    setting, damper, suite, first, stop, levels, name, signs, check = payload
    motions = [suite.motion(i) for i in range(first, stop)]
    values = np.array([motion_measure(motion, name) for motion in motions])
    scales = np.stack([scales_for(levels, value, name) for value in values])
    n = scales.size * len(signs)

    def run_at(rtol: float, factor: float, rows: np.ndarray) -> dict:
        cases = tile_cases(replace(setting, rtol=rtol), motions, scales * factor, signs, damper or {}).take(rows)
        return run_cases(cases, backend=setting.backend, threads=1)

    if tolerance_checked(check, motions[0], setting.rtol):
        result = checked_rows(run_at, setting.rtol, n)
    else:
        result = {**run_at(setting.rtol, 1.0, np.ones(n, bool)), SENSITIVE.name: np.zeros(n, dtype=bool)}
    shape = (len(motions), len(levels), len(signs))
    return {**{k: result[k].reshape(shape) for k in (*response_fields(suite), SENSITIVE.name)}, "im": values}


def tile_bounds(motions: int, per_motion: int) -> list[tuple[int, int]]:
    """The ``(first, stop)`` motions of each tile of a part of ``motions`` motions of ``per_motion`` responses
    each: about :data:`TILE_RESPONSES` responses or fewer, in :data:`MIN_TILES` tiles at least (a motion each at
    least), as even as the motions allow. A function of the study's size only, not of where it runs: a rerun finds
    its tiles whatever its workers."""
    tiles = min(motions, max(MIN_TILES, -(-motions * per_motion // TILE_RESPONSES)))
    edges = [i * motions // tiles for i in range(tiles + 1)]
    return list(zip(edges[:-1], edges[1:]))


def response_fields(suite: Suite) -> tuple[str, ...]:
    """The result fields an IDA keeps per response: the map's :data:`~rocking.study.overturning_map.FIELDS`, and its
    :data:`~rocking.study.overturning_map.FLIGHT_FIELDS` for a suite with a vertical component."""
    vertical = suite.vertical_ratio > 0.0 or bool(suite.vertical_files)
    return (*FIELDS, *FLIGHT_FIELDS) if vertical else FIELDS


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
        ``kind = "ida"`` (scale factors) or ``"fragility"`` (an intensity measure); no summary: its data
        (:func:`ida_data`) hold it. Dimensions ``part`` (``bare``, ``damper``), ``motion``, ``level``, ``sign``,
        ``curve_x``: the map's fields and ``sensitive`` (a response sensitive to the tolerance, as ``check``
        says, docs/simulation.md "Sensitivity to the tolerance") per part, motion, level and direction; ``im``
        (each motion's measure); per part and motion ``first``, ``last_safe``, ``reversals`` (a resurrection
        where it is above 0) and ``sensitive_responses``; per part and level ``fraction`` (overturned) and
        ``sensitive_fraction``; the fitted curve ``curve`` at ``curve_x`` with its band ``band_low``/``_high``
        (covering either answer of a sensitive response, :func:`~rocking.study.fragility.bootstrap_band`); per
        part the fit (:data:`FIT`: ``median``, ``dispersion`` and their intervals) and :data:`COUNTS`
        (``fit_status`` and ``median_extrapolated``, codes whose words are their ``flag_meanings``, ...).
        Where no check ran (:func:`tolerance_checked`), there is no ``sensitive`` and ``sensitive_responses`` and
        ``sensitive_fraction`` are NaN: not checked.

    Warns
    -----
    FitWarning
        A part's lognormal fitted to too few motions or of a degenerate dispersion
        (:func:`~rocking.study.fragility.fit_warnings`), or whose median lies outside the levels tested: the
        median, the level nearest to it and the fraction of the motions overturning the block there
        (:func:`~rocking.study.fragility.median_words`).
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
    im = np.full(n, np.nan)
    groups, where, folders = [], {}, {}
    shape = (len(PARTS), n, lv.size, len(signs))
    kept = response_fields(suite)
    floats = ("theta_max", "x_max", "bumper_force_max", "flight_time", "jump_max")
    fields = {k: np.zeros(shape, float if k in floats else np.int64) for k in kept}
    fields[SENSITIVE.name] = np.zeros(shape, bool)
    # One answer for the whole suite: its motions are all records and stochastic motions, or all pulses.
    is_checked = tolerance_checked(check, suite.motion(0), setting.rtol)
    for part, damper, described in zip(PARTS, (None, _damper_args(tuning)), (None, tuning.record())):
        folder = run_folder(runs, part_config("ida", part, setting, damper=described, **grids))
        folders[part] = folder.name
        tasks = []
        for first, stop in tile_bounds(n, lv.size * len(signs)):
            payload = (setting, damper, suite, first, stop, lv, measure_name, signs, check)
            size = stop - first
            expect = {**dict.fromkeys((*kept, SENSITIVE.name), (size, lv.size, len(signs))), "im": (size,)}
            task = Task(folder / f"motions-{first}-{stop}.npz", ida_tile, payload, expect)
            tasks.append(task)
            where[task.path] = (part, first, stop)
        groups.append(tasks)

    def place(task: Task, tile: dict) -> None:
        part, first, stop = where[task.path]
        for k in (*kept, SENSITIVE.name):
            fields[k][PARTS.index(part), first:stop] = tile[k]
        im[first:stop] = tile["im"]

    preflight(setting, tuning.case_args())
    stats = run_tiles(interleave(*groups), place, execution, backend=setting.backend, desc="ida", on_tile=on_tile)
    unknown = undetermined(fields["status"])
    warn_undetermined("ida", int(unknown.sum()))
    warn_t_max("ida", int(reached_t_max(fields["status"]).sum()), setting.t_after)
    positive = lv[lv > 0]
    curve_x = np.geomspace(positive.min(), positive.max(), CURVE_POINTS) if positive.size else lv
    both = response_envelope({k: fields[k] for k in FIELDS}, unknown)
    flight_counts = FLIGHT_COUNTS if "flights" in fields else ()
    results: dict[str, list] = {k: [] for k in (*RESULTS, *FIT, *COUNTS, *flight_counts)}
    for index, part in enumerate(PARTS):
        over = both["overturned"][index].astype(bool)
        ida = (
            ida_summary(lv, over)
            if lv.size > 1
            else {"first": np.full(n, np.nan), "last_safe": np.full(n, np.nan), "reversals": np.zeros(n, int)}
        )
        for k, v in ida.items():
            results[k].append(v)
        results["fraction"].append(over.mean(axis=0))
        sensitive = fields[SENSITIVE.name][index]
        # Of the responses (motions and directions), not of the envelopes: each is one run that moved. Without a
        # check nothing is known of the tolerance: NaN, not "0 sensitive".
        results["sensitive_fraction"].append(sensitive.mean(axis=(0, 2)) if is_checked else np.full(lv.size, np.nan))
        results["sensitive_responses"].append(sensitive.sum(axis=(1, 2)) if is_checked else np.full(n, np.nan))
        results["undetermined"].append(unknown[index].sum())
        if flight_counts:  # each run that flew to a verdict, by how it ended
            flew = (fields["flights"][index] > 0) & ~unknown[index]
            overturned = fields["overturned"][index].astype(bool)
            results["flies_and_lands"].append((flew & ~overturned).sum())
            results["flies_and_overturns"].append((flew & overturned).sum())
        uncertain = uncertain_verdicts(fields["overturned"][index], sensitive)
        fit, curves = _fit(lv, over, uncertain, curve_x)
        for message in _fit_messages(n, lv, results["fraction"][-1], fit, LEVELS[measure_name]):
            warnings.warn(f"{PART_NAMES[part]}: {message}", FitWarning, stacklevel=_user_stacklevel())
        for k, v in {**curves, **fit_variables(fit)}.items():
            results[k].append(v)
    kind = "ida" if measure_name == "scale" else "fragility"
    config = {"kind": kind, **setting.record(), "damper": tuning.record(), **grids, "directions": chosen}
    fields.update({k: np.stack(v) for k, v in results.items()})
    if not is_checked:
        del fields[SENSITIVE.name]  # no response was checked: none is marked either way
    return Study(
        kind,
        config,
        ida_data(config, lv, signs, curve_x, im, fields),
        run={**stats.record(), "run_folders": folders, "responses": 2 * n * lv.size * len(signs)},
        tabulate=tables,
    )


def ida_data(config: dict, levels, signs, curve_x, im, fields: dict):
    """An IDA's or a fragility's results as labelled data: the responses (:data:`FIELDS` and ``sensitive``) of
    each part, motion, level and direction, each motion's unscaled ``im``, and what the envelopes give per part:
    ``first``, ``last_safe``, ``reversals``, ``sensitive_responses`` per motion, ``fraction`` and
    ``sensitive_fraction`` per level, the fitted ``curve`` and its band at ``curve_x``, the fit (:data:`FIT`) and
    :data:`COUNTS`."""
    import xarray as xr

    coords = {
        "part": ("part", np.array(PARTS), {"long_name": "; ".join(f"{p}: {PART_NAMES[p]}" for p in PARTS)}),
        "motion": (
            "motion",
            np.array(motion_names(config["suite"])),
            {"long_name": "the motion: its file's name, <family>-T<period in s>-<i> or stochastic-<seed>-<i>"},
        ),
        **_vertical_coordinate(config["suite"]),
        "level": ("level", levels, coordinate_attrs("level", config)),
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
        "curve_x": ("curve_x", curve_x, coordinate_attrs("curve_x", config)),
    }
    variables = {k: (DIMS[k], v, field_attrs(k, config) or _own_attrs(k)) for k, v in fields.items()}
    variables["im"] = (DIMS["im"], im, field_attrs("im", config))
    return xr.Dataset(variables, coords=coords)


def _vertical_coordinate(suite: dict) -> dict:
    """The coordinate ``vertical_motion`` of a suite of records paired with vertical ones: the vertical file of
    each motion, beside its name; none for a suite without."""
    names = vertical_names(suite)
    if names is None:
        return {}
    text = "the vertical record of the motion, > 0 up, scaled with it: its file's name (docs/model.md section 14)"
    return {"vertical_motion": ("motion", np.array(names), {"long_name": text})}


def _own_attrs(name: str) -> dict:
    """CF-style attributes of a variable of :data:`OWN_FIELDS`: units, long name, the key of a code."""
    units, long_name, *key = OWN_FIELDS[name]
    attrs: dict[str, object] = {"units": units, "long_name": long_name}
    if key:
        codes: dict[int, str] = key[0]
        attrs["flag_values"] = np.array(list(codes), np.int64)
        attrs["flag_meanings"] = " ".join(codes.values())
    return attrs


def envelope(data):
    """An IDA's responses reduced over ``sign`` (:func:`rocking.study.directions.envelope`), with ``sensitive``
    where either direction is (where the responses were checked: an IDA without the check has no ``sensitive``).
    ``data``: an IDA or fragility :class:`~rocking.study.result.Study`, or its data."""
    data = directions.study_data(data, ("ida", "fragility"))
    status = data["status"]
    out = directions.envelope(data[list(FIELDS)], status.copy(data=undetermined(status.values)))
    if SENSITIVE.name in data:
        out[SENSITIVE.name] = data[SENSITIVE.name].any("sign", keep_attrs=True)
    return out


def uncertain_verdicts(overturned_by_sign, sensitive_by_sign) -> np.ndarray:
    """The envelopes (over the directions, the last axis) whose verdict the tolerance can change.

    An envelope overturns if any direction does: a sensitive direction can change it unless a
    direction that is not sensitive overturns it for certain.
    """
    overturned, sensitive = np.asarray(overturned_by_sign, bool), np.asarray(sensitive_by_sign, bool)
    return sensitive.any(axis=-1) & ~(overturned & ~sensitive).any(axis=-1)


def _user_stacklevel() -> int:
    """The ``stacklevel`` that attributes a warning of the function calling this one to the first frame outside
    the package: the user's call, through however many of the package's functions it came (the Python API's,
    the command line's)."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep
    frame: FrameType | None = sys._getframe(1)
    level = 1
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(package):
        frame, level = frame.f_back, level + 1
    return level


def _fit(levels, over, uncertain, x) -> tuple[dict, dict]:
    """The lognormal fit of one part and its band at ``x``, the band covering either verdict of the
    ``uncertain`` cells: the fit (:func:`~rocking.study.fragility.fit_lognormal`'s, with the intervals and the
    resamples of its band, NaN and 0 without a curve), and ``curve``, ``band_low``, ``band_high``."""
    fitted = levels > 0
    fit: dict = (
        fit_lognormal(levels[fitted], over[:, fitted])
        if fitted.sum() >= 2
        else {"median": np.nan, "dispersion": np.nan, "log_likelihood": np.nan, "status": "too_few_levels"}
    )
    fit["median_place"] = median_place(levels[fitted], fit)
    fit.update(median_interval=[np.nan, np.nan], dispersion_interval=[np.nan, np.nan], resamples=0)
    curves = {k: np.full(x.size, np.nan) for k in ("curve", "band_low", "band_high")}
    if fit["status"] in FITTED:
        curves["curve"] = fragility_curve(x, fit["median"], fit["dispersion"])
        band = bootstrap_band(levels[fitted], over[:, fitted], x, sensitive=uncertain[:, fitted], resamples=RESAMPLES)
        curves["band_low"], curves["band_high"] = band["low"], band["high"]
        fit.update({k: band[k] for k in ("median_interval", "dispersion_interval", "resamples")})
    return fit, curves


def _fit_messages(motions: int, levels, fraction, fit: dict, unit: str) -> list[str]:
    """Why one part's fit (:func:`_fit`) to ``motions`` motions is not to be trusted, if it is not: those of
    :func:`~rocking.study.fragility.fit_warnings`, and a median outside the ``levels`` (where ``fraction`` of the
    motions overturn the block) said with :func:`~rocking.study.fragility.median_words`."""
    out = fit_warnings(motions, fit)
    fitted = levels > 0
    words = median_words(fit["median_place"], fit["median"], levels[fitted], fraction[fitted], unit)
    if words:
        out.append(f"{words}; test {'higher' if fit['median_place'] == 'above_levels' else 'lower'} levels")
    return out


def fit_variables(fit: dict) -> dict:
    """One part's values of :data:`FIT` and :data:`COUNTS` but ``undetermined`` from its fit (:func:`_fit`): the
    median and the dispersion only where the fit gives a curve (a median of ``inf`` where nothing overturns
    is no median), the status as its code."""
    curve = fit["status"] in FITTED
    out = {k: float(fit[k]) if curve else np.nan for k in ("median", "dispersion")}
    for k in ("median", "dispersion"):
        out[f"{k}_low"], out[f"{k}_high"] = fit[f"{k}_interval"]
    out["fit_status"] = FIT_STATUSES.index(fit["status"])
    out["median_extrapolated"] = MEDIAN_PLACES.index(fit["median_place"])
    return {**out, "log_likelihood": float(fit["log_likelihood"]), "resamples": fit["resamples"]}


def tables(data, config: dict) -> dict:
    """CSV tables: ``<kind>`` (one row per motion and level: the envelope of both parts), ``<kind>-motions``
    (one row per motion: its name, its vertical record's where it has one, its measure, its first overturning and
    last safe levels, its resurrections and sensitive responses, NaN where not checked) and ``<kind>-fit`` (one row
    per part: the fitted lognormal's median and dispersion, their 90 % intervals, and :data:`COUNTS`, the fit's status
    and where its median lies as codes and words). The first has its columns ``*_sensitive`` only where the
    responses were checked."""
    kind, env = config["kind"], envelope(data)
    names = data["motion"].values
    motion, level = np.meshgrid(np.arange(names.size), data["level"].values, indexing="ij")
    rows = {"motion": names[motion.ravel()], "level": level.ravel()}
    for part in PARTS:
        for k in ("overturned", "impacts", "theta_max", "x_max", SENSITIVE.name):
            if k in env:  # no column of sensitive responses where none was checked
                rows[f"{part}_{k}"] = env[k].sel(part=part).values.ravel()
    motions = {"motion": names}
    if "vertical_motion" in data.coords:
        motions["vertical_motion"] = data["vertical_motion"].values
    motions["im"] = data["im"].values
    for part in PARTS:
        for k in ("first", "last_safe", "reversals", "sensitive_responses"):
            motions[f"{part}_{k}"] = data[k].sel(part=part).values
    # A study saved before median_extrapolated was kept (its format is the same) still loads, without that column.
    fits = {"part": np.array(PARTS), **{k: data[k].values for k in (*FIT, *COUNTS) if k in data}}
    return {kind: rows, f"{kind}-motions": motions, f"{kind}-fit": fits}
