"""The minimum overturning spectrum ``beta_min(Omega)``, with the safe windows above it.

``beta_min`` is the smallest amplitude ratio ``beta`` of a one-sine pulse of
frequency ratio ``Omega`` that overturns the block (``docs/model.md`` section 9).
The overturning domain is not monotone in ``beta`` (``docs/model.md`` 10.4: above
the first overturning amplitude there are windows where the block survives),
so a bisection from a safe to an overturning amplitude alone could land on
any of its edges. :func:`beta_min` therefore

1. scans ``beta`` on a grid, every amplitude, in one call of :func:`rocking.sim.cases.run_cases` for every
   column of a tile at once,
2. bisects between the last safe scan amplitude below the first overturning
   one and that one, to a relative tolerance ``tol``; ``beta_min`` is the
   smallest amplitude found to overturn (the upper end of the final bracket),
3. reports the *windows*: runs of safe scan amplitudes above ``beta_min``
   (:func:`windows`). A window is known to the resolution of the scan: it
   extends from its first to its last safe scan point, plus less than one
   scan step at either end; windows narrower than a step may be missed.

Each column's ``flag`` says how ``beta_min`` was found: ``BRACKETED`` (0,
bisected), ``BELOW`` (-1: the first scan amplitude overturns already;
``beta_min`` is then that amplitude, an upper bound) or ``ABOVE`` (+1: no
scan amplitude overturns; ``beta_min`` is then the last one, a lower bound).

Every scan amplitude is computed, and no scan can do with fewer and give the same ``beta_min``: the
overturning domain has bands of a single amplitude amid safe ones (bench spectrum, Omega = 3, negative pulses,
with the damper: only beta = 1.875 overturns below 3.25), and a band that no computed amplitude falls in
leaves no trace in the outcomes around it. An exact ``beta_min`` needs the outcome of every amplitude below
it, and the windows of every one above: on the default grids, the amplitudes up to the first overturning one
are 70 % of the scan and 73 % of its CPU time (5 pulse families, both signs, bare, with a damper, with stops;
bench/adaptive_spectrum.py). The adaptive scans of earlier versions (``--coarse``) skipped the rest and could
move ``beta_min`` up by more than 100 % (issue 35), for 1.0 to 1.25 times less CPU time: they are gone.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..model.params import ParameterError
from ..sim.problem import STATUS
from .config import Grid, Setting, Tuning, Variant, floor_attrs, is_count, is_number, part_config, vertical_attrs
from .dataset import SI_AMPLITUDES, coordinate_attrs, field_attrs, si_amplitudes, si_coordinates
from .directions import SIGN_NAMES, beta_min_envelope, choose, repeat, sign_column, study_data, take
from .overturning_map import (
    FIXED,
    PARTS,
    check_damper,
    check_study,
    preflight,
    reached_t_max,
    respond,
    response_classes,
    undetermined,
    warn_t_max,
    warn_undetermined,
)
from .result import Study
from .tiles import LOCAL, Execution, Task, interleave, run_folder, run_tiles
from .vocabulary import ABOVE, BELOW, BRACKETED, FLIGHT, PART_NAMES, SAFE, flag_words

#: Default relative tolerance of the bisection on beta.
TOL = 1e-3

#: Default Omega columns per tile. Each step of the bisection is one call of
#: run_cases for all the columns of a tile: with one column per call the
#: Python around it, which holds the GIL, would stop local worker threads
#: from running in parallel.
COLUMNS = 8
#: What :func:`beta_min` gives per column (each of shape (n,)), besides ``scan_outcome`` and the counts of
#: :data:`RESPONSE_COUNTS`.
COLUMN_FIELDS = ("beta_min", "beta_safe", "flag", "impacts", "undetermined")
#: What :func:`beta_min` gives per column beside :data:`COLUMN_FIELDS` where the pulses have a vertical component
#: (docs/model.md section 16): the responses that flew and landed to a verdict, and whether the one that overturns
#: at ``beta_min`` flew first (flies and overturns).
FLIGHT_COLUMNS = ("flown", "beta_min_flew")

#: The variables of a censored ``beta_min`` (:func:`censored`) and of its amplitude in SI units, and their columns
#: in the CSV, in order.
CENSORED = ("beta_min_lower_bound", *SI_AMPLITUDES)

#: The dimensions of every variable of a spectrum's data (:func:`spectrum_data`), coordinates included.
DIMS = {
    "part": ("part",),
    "Omega": ("Omega",),
    "beta_scan": ("beta_scan",),
    "sign": ("sign",),
    "T_g": ("Omega",),
    "a_g_beta_scan": ("beta_scan",),
    **dict.fromkeys((*COLUMN_FIELDS, *FLIGHT_COLUMNS, *CENSORED), ("part", "Omega", "sign")),
    "scan_outcome": ("part", "Omega", "sign", "beta_scan"),
}
#: How many responses :func:`beta_min` computed per column: in all, and of them for the scan.
RESPONSE_COUNTS = ("responses", "scan_responses")
#: The counts per column of :func:`beta_min`'s responses that ended without a verdict, and that reached ``t_max``.
UNFINISHED = ("undetermined", "t_max")

#: How a spectrum's scans are refined, as its configuration records it: not at all, every amplitude is computed
#: (module docstring). Recorded still so that the configurations, and the tiles, of the full scans of earlier
#: versions keep their keys, and a study saved with their adaptive scans (``{"adaptive": True, "coarse": ...}``)
#: says so (:func:`adaptive_scans`).
FULL_SCAN = {"adaptive": False}


def check_tol(tol) -> float:
    """The bisection tolerance, validated: a number in (0, 0.1]."""
    if not (is_number(tol) and 0 < tol <= 0.1):
        raise ParameterError(f"beta_tol must be a relative tolerance in (0, 0.1] (got {tol!r})")
    return float(tol)


def adaptive_scans(config: dict) -> int:
    """The coarse step of the adaptive scans of a spectrum saved by an earlier version (``config["refinement"]``),
    0 for one that scanned every amplitude: such a study's ``beta_min`` can be too high (module docstring)."""
    refinement = config.get("refinement", FULL_SCAN)
    return int(refinement.get("coarse", 0)) if refinement.get("adaptive") else 0


def _column(values, n: int) -> dict | None:
    """Damper keyword arrays as columns ``(n, 1)``, to broadcast against the scan amplitudes.

    ``model`` and ``params`` (:data:`rocking.study.overturning_map.FIXED`) pass through unchanged.
    """
    if values is None:
        return None
    return {k: v if k in FIXED else np.broadcast_to(np.asarray(v, float), (n,))[:, None] for k, v in values.items()}


def beta_min(setting: Setting, Omega, beta_scan, damper: dict | None = None, *, tol: float = TOL, sign=1) -> dict:
    """Minimum overturning amplitude of each column ``(Omega[i], damper[.][i], sign[i])``: scan, then bisection.

    Parameters
    ----------
    setting : Setting
        Block and solver.
    Omega : array_like, shape (n,)
        Pulse frequency ratio of each column.
    beta_scan : array_like, shape (m,)
        Increasing scan amplitudes.
    damper : dict, optional
        Keyword arguments of :func:`rocking.sim.cases.pulse_cases` (``gamma``,
        ``omega_ratio``, ``zeta``, ``h``), scalars or arrays of shape (n,),
        or ``model`` and ``params`` (:meth:`Variant.case_args`); ``None`` for
        the bare block.
    tol : float
        Relative width of the final bracket, ``(hi - lo) <= tol * hi``.
    sign : int or array_like, shape (n,)
        Direction of the pulses of each column, +1 or -1.
    Returns
    -------
    dict of ndarray
        ``beta_min`` (n,), ``beta_safe`` (n,: lower end of the final bracket,
        ``nan`` unless bracketed), ``flag`` (n,), ``impacts`` (n,: impacts
        before overturning at ``beta_min``, -1 if none), ``undetermined``
        (n,: responses of the scan and the bisection that ended without a
        verdict, :func:`rocking.study.overturning_map.undetermined`; they
        count as not overturned), ``t_max`` (n,: responses computed that reached ``t_max``,
        :func:`rocking.study.overturning_map.reached_t_max`), ``scan_outcome`` (n, m:
        :func:`rocking.study.overturning_map.outcome` along the scan, :data:`~rocking.study.vocabulary.FLIGHT`
        where a run ended in flight: a column is read below its first flight only), ``responses``
        (n,: responses computed, scan and bisection) and ``scan_responses`` (n,: of them, the scan's); with a
        vertical component :data:`FLIGHT_COLUMNS`: ``flown`` (n,: responses of the scan and the bisection that
        flew and came to a verdict) and ``beta_min_flew`` (n,: 1 where the response that overturns at
        ``beta_min`` flew first, 0 elsewhere).
    """
    Omega = np.atleast_1d(np.asarray(Omega, float))
    beta_scan = np.asarray(beta_scan, float)
    n = Omega.size
    cols = _column(damper, n)
    sign = np.broadcast_to(np.asarray(sign), (n,))
    t_max = np.zeros(n, np.int64)

    r = respond(setting, Omega[:, None], beta_scan[None, :], cols, sign[:, None])
    t_max += reached_t_max(r["status"]).sum(axis=1)
    classes = response_classes(r["overturned"], r["impacts"], r["status"])
    scan_outcome = np.where(classes >= 0, classes, SAFE)  # no verdict (class <= -2): not overturned
    # On a model without flight functions a run that ended in flight has no verdict, nor has the scan above it
    # (every run there flies unless it overturns first, docs/model.md section 14): a column is read up to its first
    # flight, the lower bound of a beta_min not reached is the amplitude before it, and the flights keep their own
    # outcome (no safe window). A flight model's runs fly and land to a verdict (section 16): no status flight.
    flight = classes == -2 - STATUS.index("flight")
    flown = np.cumsum(flight, axis=1) > 0
    scan_outcome = np.where(flight, FLIGHT, scan_outcome)
    over = (scan_outcome >= 0) & ~flown
    first = np.argmax(over, axis=1)  # first overturning scan point (0 if none)
    rows = np.arange(n)
    flag = np.where(~over.any(axis=1), ABOVE, np.where(first == 0, BELOW, BRACKETED))
    top = np.where(flown.any(axis=1), np.maximum(np.argmax(flown, axis=1) - 1, 0), beta_scan.size - 1)
    hi = np.where(flag == ABOVE, beta_scan[top], beta_scan[first])
    lo = np.where(flag == BRACKETED, beta_scan[np.maximum(first - 1, 0)], np.nan)
    impacts = np.where(flag == ABOVE, -1, scan_outcome[rows, first])
    unknown = (classes <= -2).sum(axis=1)
    flew = _flew(r["flights"], classes) if "flights" in r else None  # (n, m); a vertical component only
    if flew is not None:
        flown_runs, beta_min_flew = flew.sum(axis=1), np.where(flag == ABOVE, False, flew[rows, first])
    scan_responses = np.full(n, beta_scan.size, np.int64)
    responses = scan_responses.copy()
    while True:
        active = np.flatnonzero((flag == BRACKETED) & (hi - lo > tol * hi))
        if active.size == 0:
            break
        mid = 0.5 * (lo[active] + hi[active])
        sub = None if cols is None else {k: v if k in FIXED else v[active, 0] for k, v in cols.items()}
        r = respond(setting, Omega[active], mid, sub, sign[active])
        up = r["overturned"]
        hi[active[up]], impacts[active[up]] = mid[up], r["impacts"][up]
        lo[active[~up]] = mid[~up]
        if flew is not None:
            flew_mid = _flew(r["flights"], response_classes(r["overturned"], r["impacts"], r["status"]))
            flown_runs[active] += flew_mid
            beta_min_flew[active[up]] = flew_mid[up]
        unknown[active] += undetermined(r["status"])
        t_max[active] += reached_t_max(r["status"])
        responses[active] += 1
    return {
        "beta_min": hi,
        "beta_safe": lo,
        "flag": flag,
        "impacts": impacts,
        "undetermined": unknown,
        "t_max": t_max,
        "scan_outcome": scan_outcome,
        "responses": responses,
        "scan_responses": scan_responses,
        **({} if flew is None else {"flown": flown_runs, "beta_min_flew": beta_min_flew.astype(np.int64)}),
    }


def _flew(flights, classes) -> np.ndarray:
    """Where responses flew (their ``flights``) and came to a verdict (their ``classes``,
    :func:`rocking.study.overturning_map.response_classes`: no status without a verdict)."""
    return (np.asarray(flights) > 0) & (np.asarray(classes) > -2)


def unfinished(counts: dict) -> np.ndarray:
    """The totals of the counts :data:`UNFINISHED` of ``counts`` (results of :func:`beta_min` or of an envelope
    of them that keeps both)."""
    return np.array([int(np.sum(counts[k])) for k in UNFINISHED])


def windows(beta_scan, scan_overturned) -> np.ndarray:
    """Safe windows above the first overturning scan point, shape (k, 2): first and last safe amplitude.

    A window that reaches the end of the scan ends there (it may go on).
    """
    over = np.asarray(scan_overturned, bool)
    if not over.any():
        return np.zeros((0, 2))
    safe = ~over
    safe[: np.argmax(over)] = False
    edges = np.diff(np.concatenate([[0], safe.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    beta_scan = np.asarray(beta_scan, float)
    return np.column_stack([beta_scan[starts], beta_scan[stops]])


def spectrum_tile(payload: tuple) -> dict:
    """Some columns in every direction: ``(setting, damper_or_None, Omega values, beta_scan, tol, signs)`` ->
    :func:`beta_min` of them, each array with an axis of the signs after that of ``Omega``."""
    setting, damper, Omega, beta_scan, tol, signs = payload
    res = beta_min(setting, repeat(Omega, signs), beta_scan, damper, tol=tol, sign=sign_column(len(Omega), signs))
    return {k: v.reshape(len(Omega), len(signs), *v.shape[1:]) for k, v in res.items()}


def minimum_overturning_spectrum(
    setting: Setting,
    tuning: Tuning | Variant,
    Omega: Grid,
    beta: Grid,
    execution: Execution = LOCAL,
    *,
    tol: float = TOL,
    runs: str | Path = "out/runs",
    columns: int = COLUMNS,
    directions: str = "auto",
    on_tile=None,
) -> Study:
    """``beta_min(Omega)`` of the bare block and with the damper ``tuning``, ``columns`` Omega values per tile;
    in both directions of the pulse, and their envelope (the smaller ``beta_min``).

    Parameters
    ----------
    setting : Setting
        Block and solver.
    tuning : Tuning or Variant
        The damper: the paper's ``omd`` relative to the block, or any
        generated model with its parameters.
    Omega : Grid
        Pulse frequency ratios.
    beta : Grid
        Scan amplitudes, every one computed; the scan step bounds the width of the windows and of the
        overturning bands seen.
    execution : Execution
        Where the tiles run.
    tol : float
        Relative tolerance of the bisection.
    runs : path
        Folder of the run folders.
    columns : int
        Omega values per tile.
    directions : {"auto", "both", "positive", "negative"}
        Signs of the pulses (:func:`rocking.study.directions.choose`): ``"auto"`` runs both unless the block
        and its damper are symmetric.
    on_tile : callable, optional
        Passed to :func:`rocking.study.tiles.run_tiles`.

    Returns
    -------
    Study
        Its data (:func:`spectrum_data`): the :func:`beta_min` results of each direction, dimensions
        ``(part, Omega, sign)`` (``part``: ``bare`` and ``damper``), ``scan_outcome`` also along ``beta_scan``.
        Their envelope over the directions (the smaller ``beta_min``, the direction that gives it) is a
        reduction over ``sign`` (:func:`envelope`), and the safe windows above it are read from its scan
        (:func:`safe_windows`). ``config["refinement"]`` records that every amplitude was scanned
        (:data:`FULL_SCAN`); ``run["responses"]`` counts the responses computed (scans and bisections),
        ``run["scan_responses"]`` those of the scans. ``summary["t_max"]`` counts, per part, the responses that
        reached ``t_max``.

    Raises
    ------
    ParameterError
        Naming the parameter and its valid range, before any work: inputs of
        the wrong type, more than
        :data:`rocking.study.config.MAX_CELLS` cells, a folder that cannot be written, a back end or a Dask
        cluster that cannot be used.
    rocking.study.tiles.Interrupted
        On Ctrl-C (a KeyboardInterrupt): the finished tiles are kept in
        ``runs``, and the same call resumes from them.

    Warns
    -----
    rocking.study.tiles.TileWarning
        For a stored tile that is damaged or foreign: it is computed again.
    rocking.study.overturning_map.UndeterminedWarning
        For responses that ended without a verdict (:func:`rocking.study.overturning_map.warn_undetermined`).
    rocking.study.overturning_map.TMaxWarning
        For responses that reached ``t_max``: they count as not overturned
        (:func:`rocking.study.overturning_map.warn_t_max`).

    Examples
    --------
    >>> import tempfile, rocking
    >>> from rocking.study.spectrum import minimum_overturning_spectrum
    >>> study = minimum_overturning_spectrum(
    ...     rocking.Setting(rocking.Block.reference()), rocking.Tuning(0.05),
    ...     rocking.Grid("Omega", 2.0, 6.0, 3), rocking.Grid("beta", 0.5, 15.0, 30),
    ...     rocking.Execution(workers=1, progress=False), runs=tempfile.mkdtemp())
    >>> study.data["beta_min"].sel(part="bare").values.round(2)  # columns: sign +1, -1 (the block is eccentric)
    array([[1.28, 1.15],
           [1.6 , 1.91],
           [2.82, 8.66]])
    >>> from rocking.study.spectrum import envelope
    >>> envelope(study.data)["beta_min"].values.round(2)  # the envelopes: rows bare, damper
    array([[1.15, 1.6 , 2.82],
           [1.25, 1.79, 3.97]])
    """
    check_study(setting, execution, runs, Omega=Omega, beta=beta)
    tol = check_tol(tol)
    if not (is_count(columns) and columns >= 1):
        raise ParameterError(f"columns must be an integer >= 1 (Omega values per tile) (got {columns!r})")
    columns = int(columns)
    check_damper(tuning)
    chosen = choose(directions, setting.block, tuning)
    signs = chosen["signs"]
    Om, b = Omega.values(), beta.values()
    grids = {
        "Omega": Omega.record(),
        "beta": beta.record(),
        "beta_tol": tol,
        "columns": columns,
        "signs": signs,
        "refinement": FULL_SCAN,
    }
    record = tuning.record()
    groups, where, folders = [], {}, {}
    ns = len(signs)
    columns_kept = (*COLUMN_FIELDS, *(FLIGHT_COLUMNS if setting.vertical is not None else ()))
    integers = ("flag", "impacts", "undetermined", *columns_kept[len(COLUMN_FIELDS) :])
    fields = {
        **{k: np.full((len(PARTS), Om.size, ns), np.nan) for k in ("beta_min", "beta_safe")},
        **{k: np.zeros((len(PARTS), Om.size, ns), np.int64) for k in integers},
        "scan_outcome": np.zeros((len(PARTS), Om.size, ns, b.size), np.int64),
    }
    for part, damper, described in zip(PARTS, (None, tuning.case_args()), (None, record)):
        folder = run_folder(runs, part_config("spectrum", part, setting, damper=described, **grids))
        folders[part] = folder.name
        part_tasks: list[Task] = []
        groups.append(part_tasks)
        for i in range(0, Om.size, columns):
            cols = slice(i, min(i + columns, Om.size))
            payload = (setting, damper, Om[cols], b, tol, signs)
            n = cols.stop - cols.start
            expect = {
                **dict.fromkeys((*columns_kept, *RESPONSE_COUNTS, "t_max"), (n, ns)),
                "scan_outcome": (n, ns, b.size),
            }
            task = Task(folder / f"columns-{cols.start}-{cols.stop}.npz", spectrum_tile, payload, expect)
            part_tasks.append(task)
            where[task.path] = (part, cols)

    counts = dict.fromkeys(RESPONSE_COUNTS, 0)
    t_max = dict.fromkeys(PARTS, 0)

    def place(task: Task, tile: dict) -> None:
        part, cols = where[task.path]
        for k in (*columns_kept, "scan_outcome"):
            fields[k][PARTS.index(part), cols] = tile[k]
        for k in RESPONSE_COUNTS:
            counts[k] += int(tile[k].sum())
        t_max[part] += int(tile["t_max"].sum())

    preflight(setting, tuning.case_args())
    stats = run_tiles(interleave(*groups), place, execution, backend=setting.backend, desc="spectrum", on_tile=on_tile)
    warn_undetermined("spectrum", int(fields["undetermined"].sum()))
    warn_t_max("spectrum", sum(t_max.values()), setting.t_after)
    config = {"kind": "spectrum", **setting.record(), "damper": record, **grids, "directions": chosen}
    data = spectrum_data(config, Om, b, signs, fields)
    return Study(
        "spectrum",
        config,
        data,
        summary={**spectrum_summary(data), "t_max": t_max, "directions": chosen, "refinement": FULL_SCAN},
        run={**stats.record(), "run_folders": folders, **counts},
        tabulate=spectrum_tables,
    )


def censored(fields: dict) -> dict:
    """``fields`` (:func:`beta_min`'s, or their envelope's) with each ``beta_min`` not reached in the scan (flag
    ``ABOVE``) stored as a censored value: ``beta_min`` NaN, and ``beta_min_lower_bound`` the last amplitude
    scanned without overturning (NaN where ``beta_min`` is a value): no plot or table in SI reads the scan's end as
    a measured ``beta_min``."""
    above = np.asarray(fields["flag"]) == ABOVE
    beta = np.asarray(fields["beta_min"], float)
    return {**fields, "beta_min": np.where(above, np.nan, beta), "beta_min_lower_bound": np.where(above, beta, np.nan)}


def beta_min_or_bound(data) -> np.ndarray:
    """The ``beta_min`` of a spectrum's data with the lower bound in place of each censored one (:func:`censored`;
    the ``flag`` says which is which): what the envelope over the directions and the gains compare. A spectrum
    saved before the censoring has the bound in ``beta_min`` already."""
    beta = data["beta_min"].values
    if "beta_min_lower_bound" not in data:
        return beta
    return np.where(np.isnan(beta), data["beta_min_lower_bound"].values, beta)


def spectrum_data(config: dict, Omega, beta_scan, signs, fields: dict):
    """A spectrum's results as labelled data: the :data:`COLUMN_FIELDS` of each part, Omega and direction (a
    ``beta_min`` not reached in the scan :func:`censored`), and ``scan_outcome`` along ``beta_scan`` too, with the
    coordinates in non-dimensional and SI terms and units."""
    import xarray as xr

    fields = censored(fields)
    fields |= si_amplitudes(config, fields)

    coords = {
        "part": ("part", np.array(PARTS), {"long_name": "; ".join(f"{p}: {PART_NAMES[p]}" for p in PARTS)}),
        "Omega": ("Omega", Omega, coordinate_attrs("Omega", config)),
        "beta_scan": ("beta_scan", beta_scan, coordinate_attrs("beta_scan", config)),
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
    }
    coords.update(si_coordinates(config, coords))
    variables = {k: (DIMS[k], v, field_attrs(k, config)) for k, v in fields.items()}
    return xr.Dataset(variables, coords=coords, attrs={**vertical_attrs(config), **floor_attrs(config)})


def envelope(data):
    """A spectrum's results reduced over ``sign`` (:func:`rocking.study.directions.beta_min_envelope`): the
    smaller ``beta_min`` of the directions of each part and Omega, its ``beta_safe``, ``flag`` and
    ``impacts``, the responses without a verdict summed, the worse ``scan_outcome`` at each scan amplitude,
    and ``worst_sign``. ``data``: a spectrum :class:`~rocking.study.result.Study` or its data."""
    import xarray as xr

    data = study_data(data, ("spectrum",))
    by_sign = {k: data[k].values for k in (*COLUMN_FIELDS, *FLIGHT_COLUMNS, "scan_outcome") if k in data}
    reduced = censored(beta_min_envelope({**by_sign, "beta_min": beta_min_or_bound(data)}))
    index = reduced.pop("worst_sign_index")
    reduced |= {k: take(data[k].values, index) for k in SI_AMPLITUDES if k in data}  # the governing direction's
    out = xr.Dataset(
        {
            k: (tuple(d for d in DIMS[k] if d != "sign"), v, data[k].attrs if k in data else field_attrs(k, {}))
            for k, v in reduced.items()
        },
        coords=data.drop_dims("sign").coords,
    )
    out["worst_sign"] = (("part", "Omega"), data["sign"].values[index], field_attrs("worst_sign", {}))
    return out


def safe_windows(env, part: str) -> np.ndarray:
    """The safe windows above ``beta_min`` of ``part`` in a spectrum's :func:`envelope`: rows ``(Omega, first
    safe, last safe)`` (:func:`windows`)."""
    return _all_windows(env["Omega"].values, env["beta_scan"].values, env["scan_outcome"].sel(part=part).values)


def _all_windows(Omega, beta_scan, scan_outcome) -> np.ndarray:
    """Windows of every column, stacked as rows ``(Omega, first safe, last safe)``."""
    rows = []
    for Om, column in zip(Omega, scan_outcome):
        w = windows(beta_scan, column != SAFE)
        rows.append(np.column_stack([np.full(len(w), Om), w]))
    return np.concatenate(rows)


def spectrum_tables(data, config: dict) -> dict:
    """CSV tables: ``spectrum`` (one row per Omega: the envelope and, with two directions, each direction's
    ``beta_min``) and ``spectrum-windows`` (one row per window)."""
    env = envelope(data)
    main = {"Omega": data["Omega"].values, "T_g": data["T_g"].values}
    windows_table: dict[str, list] = {"part": [], "Omega": [], "T_g": [], "beta_first_safe": [], "beta_last_safe": []}
    period = dict(zip(main["Omega"].tolist(), main["T_g"].tolist()))
    signs = data["sign"].values
    for part in PARTS:
        a, by_sign = env.sel(part=part), data.sel(part=part)
        for k in ("beta_min", *CENSORED, *COLUMN_FIELDS[1:], *FLIGHT_COLUMNS):
            if k in a:  # a spectrum saved before the censoring has none of CENSORED
                main[f"{part}_{k}"] = a[k].values
        main[f"{part}_beta_min_is"] = flag_words(a["flag"].values)
        if signs.size > 1:
            main[f"{part}_worst_sign"] = a["worst_sign"].values
            for i, sign in enumerate(signs):
                main[f"{part}_beta_min_{SIGN_NAMES[sign]}"] = by_sign["beta_min"].values[:, i]
                bound = by_sign["beta_min_lower_bound"].values[:, i] if "beta_min_lower_bound" in by_sign else None
                main[f"{part}_beta_min_lower_bound_{SIGN_NAMES[sign]}"] = (
                    np.full(main["Omega"].size, np.nan) if bound is None else bound
                )
                main[f"{part}_flag_{SIGN_NAMES[sign]}"] = by_sign["flag"].values[:, i]
        w = safe_windows(env, part)
        main[f"{part}_windows"] = np.array([np.sum(w[:, 0] == Om) for Om in main["Omega"]])
        windows_table["part"] += [part] * len(w)
        windows_table["Omega"] += list(w[:, 0])
        windows_table["T_g"] += [period[Om] for Om in w[:, 0].tolist()]
        windows_table["beta_first_safe"] += list(w[:, 1])
        windows_table["beta_last_safe"] += list(w[:, 2])
    return {"spectrum": main, "spectrum-windows": {k: np.asarray(v) for k, v in windows_table.items()}}


def gain_summary(env) -> dict:
    """The damper's gain over the frequencies where it is defined, from a spectrum's :func:`envelope` ``env``.

    The gain is the ratio of the envelopes' ``beta_min``, damper over bare, where the bare block's is bracketed
    and the damper's not below the scan (a damper's ``beta_min`` not reached in the scan counts by its lower
    bound). Returns ``frequencies`` (how many), ``min``, ``max`` (None where there are none) and ``below_1`` (at
    how many the damper makes the block overturn at a smaller amplitude), and ``text``, the sentence a command
    prints.
    """
    flag = {part: env["flag"].sel(part=part).values for part in ("bare", "damper")}
    beta_min = {part: beta_min_or_bound(env.sel(part=part)) for part in ("bare", "damper")}
    both = (flag["bare"] == BRACKETED) & (flag["damper"] != BELOW)
    if not both.any():
        text = "gain of the damper undefined at every frequency (the bare block's beta_min is outside the scan)"
        return {"frequencies": 0, "min": None, "max": None, "below_1": 0, "text": text}
    gain = beta_min["damper"][both] / beta_min["bare"][both]
    out: dict = {"frequencies": int(both.sum()), "min": float(gain.min()), "max": float(gain.max())}
    out["below_1"] = int((gain < 1).sum())
    out["text"] = (
        f"gain of the damper (the ratio of the envelopes) from {out['min']:.3g} to {out['max']:.3g} over "
        f"{out['frequencies']} frequencies; below 1 at {out['below_1']}"
    )
    return out


def spectrum_summary(data) -> dict:
    """Columns bracketed / out of the scan range, and windows found, per part; the damper's gain
    (:func:`gain_summary`)."""
    env = envelope(data)
    out: dict = {"gain": gain_summary(env)}
    for part in PARTS:
        flag = env["flag"].sel(part=part).values
        out[part] = {
            "bracketed": int((flag == BRACKETED).sum()),
            "overturned_at_first_scan_point": int((flag == BELOW).sum()),
            "not_overturned_in_scan": int((flag == ABOVE).sum()),
            "windows": int(len(safe_windows(env, part))),
            "undetermined": int(env["undetermined"].sel(part=part).values.sum()),
        }
        if "flown" in env:  # a vertical component: the responses that flew and landed to a verdict
            out[part]["flown"] = int(env["flown"].sel(part=part).values.sum())
            out[part]["beta_min_flew"] = int(env["beta_min_flew"].sel(part=part).values.sum())
    return out
