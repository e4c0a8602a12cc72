"""The threshold frequency ``Omega*`` across block geometries, for the unlimited damper and the damper with stops.

The paper's headline is a threshold pulse frequency above which the damper is
useless. :func:`threshold_map` computes it over a grid of slenderness
``lambda = H / B`` and size ``p`` (the blocks of :meth:`rocking.Block.from_nondim`,
eccentricity ``e = e_ratio B``), for the ``omd`` damper of a :class:`Tuning`
with the paper's unlimited guide and with the stops of
:meth:`rocking.Stops.at_edges`, over both directions of the pulse.

At each ``(lambda, p, Omega)`` (one tile), the best gain over the damper period
(:func:`rocking.study.optimize.refinement` around the best of a coarse log grid of
``r = T_m p / (2 pi)``) is the ratio of the envelopes of ``beta_min`` over the
directions; ``Omega*`` is where it falls below
:data:`rocking.study.optimize.USELESS_GAIN` for good
(:func:`rocking.study.optimize.threshold_frequency`).

The amplitude scan extends itself
---------------------------------
``beta_min`` grows with ``Omega``: a fixed top of the ``beta`` scan would end
every gain at a lower bound and hide ``Omega*``. Each ``beta_min`` here
(:func:`rising_beta_min`) scans ``[BETA_START, top]``, and where nothing
overturns doubles ``top``, scanning ``[top, 2 top]``, until an amplitude
overturns the block or the scan passes the physical bound of the ground
acceleration, ``a_g <= a_max`` (default :data:`A_MAX` = 4 g), i.e.
``beta <= a_max / (g tan(alpha))``. Where the block alone does not overturn
within that bound, no pulse of plausible amplitude overturns it: the gain is
not defined there, and the study reports from which ``Omega`` on
(``safe_from``).

Units SI (m, kg, s); ``p`` in rad/s; the pulse parameters are non-dimensional.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..model.params import Block, ParameterError, check_real
from .config import Grid, Setting, Tuning, part_config
from .dataset import coordinate_attrs, field_attrs
from .directions import beta_min_envelope, choose, repeat, sign_column
from .optimize import USELESS_GAIN, at_edge, coarse_values, refinement, threshold_frequency
from .overturning_map import FIXED, check_study, preflight, warn_t_max, warn_undetermined
from .result import Study
from .spectrum import TOL, UNFINISHED, beta_min, check_tol, unfinished
from .tiles import LOCAL, Execution, Task, run_folder, run_tiles
from .vocabulary import ABOVE, BRACKETED, PART_NAMES
from .vocabulary import THRESHOLD_STATUSES as STATUSES

#: Default bound of the ground acceleration, in units of g. The largest peak ground acceleration ever
#: recorded is 4.36 g (vector sum of three components, KiK-net station IWTH25, 2008 Iwate-Miyagi
#: Nairiku earthquake; Yamada et al. 2009, Seismological Research Letters 80(5)); horizontal peaks
#: stay below it.
A_MAX = 4.0

#: First amplitude and points per segment of a rising scan (docs/model.md section 9: uplift starts near
#: beta = 1, so 0.5 starts below it).
BETA_START, SCAN_POINTS = 0.5, 24
#: Top of the first segment of a rising scan.
BETA_TOP = 6.0

#: The dampers compared: the paper's unlimited guide and the stops at the block's edges.
KINDS = ("unlimited", "stops")

#: Default grids: slenderness, size (rad/s), pulse frequency ratio, damper period r = T_m p / (2 pi).
LAM_GRID, P_GRID, OMEGA_GRID, TM_GRID = (2.0, 8.0, 4), (1.0, 5.0, 3), (1.0, 22.0, 15), (0.1, 10.0, 9)


def beta_bound(block: Block, a_max: float) -> float:
    """The largest amplitude ratio of the bound ``a_g <= a_max g``: ``a_max / tan(alpha)``."""
    return a_max / block.tan_alpha


def rising_beta_min(setting: Setting, Omega, damper, *, sign, beta_max: float, tol: float) -> dict:
    """:func:`rocking.study.spectrum.beta_min` of each column, the scan rising until it overturns or passes
    ``beta_max``.

    Segments ``[BETA_START, BETA_TOP]``, then ``[top, 2 top]`` (the last one ending at ``beta_max``), each
    of :data:`SCAN_POINTS` amplitudes, for the columns that have not overturned yet. Returns the arrays of
    ``beta_min`` (``flag`` ``ABOVE``: no overturning up to ``beta_max``) and ``top``, the end of the last
    segment of each column.
    """
    Omega = np.atleast_1d(np.asarray(Omega, float))
    n = Omega.size
    sign = np.broadcast_to(np.asarray(sign), (n,))
    columns = None if damper is None else {k: v if k in FIXED else np.broadcast_to(v, (n,)) for k, v in damper.items()}
    out = {k: np.full(n, np.nan) for k in ("beta_min", "beta_safe", "top")}
    out.update({k: np.zeros(n, np.int64) for k in ("flag", "impacts", *UNFINISHED)})
    todo, low, high = np.arange(n), BETA_START, min(BETA_TOP, beta_max)
    while todo.size:
        sub = None if columns is None else {k: v if k in FIXED else v[todo] for k, v in columns.items()}
        res = beta_min(setting, Omega[todo], np.linspace(low, high, SCAN_POINTS), sub, tol=tol, sign=sign[todo])
        for k in ("beta_min", "beta_safe", "flag", "impacts"):
            out[k][todo] = res[k]
        for k in UNFINISHED:
            out[k][todo] += res[k]
        out["top"][todo] = high
        if high >= beta_max:
            break
        todo = todo[res["flag"] == ABOVE]
        low, high = high, min(2 * high, beta_max)
    return out


def _envelope(setting, Omega: float, damper, n: int, signs, beta_max, tol) -> dict:
    """Envelope over ``signs`` of :func:`rising_beta_min` for the ``n`` columns of ``damper`` (scalars or arrays
    (n,)), or the bare block (``damper`` None, ``n = 1``)."""
    cols = None
    if damper is not None:
        cols = {k: v if k in FIXED else repeat(np.broadcast_to(v, (n,)), signs) for k, v in damper.items()}
    res = rising_beta_min(
        setting, np.full(n * len(signs), Omega), cols, sign=sign_column(n, signs), beta_max=beta_max, tol=tol
    )
    by_sign = {k: v.reshape(n, len(signs)) for k, v in res.items() if k != "top"}
    return {**beta_min_envelope(by_sign), "t_max": by_sign["t_max"].sum(axis=-1)}


def best_gain(setting, Omega: float, tuning: Tuning, r_coarse, refine: int, reference: float, signs, beta_max, tol):
    """Best gain over the damper period at ``Omega``: coarse ``r`` grid, then ``refine`` points each side of the
    best. Returns ``(gain, r, flag)`` of the best point (ties to the shorter period) and the counts
    :data:`UNFINISHED` of the search."""
    base = {k: v for k, v in tuning.case_args().items() if k != "omega_ratio"}
    r_all, gains, flags, unknown = [], [], [], np.zeros(len(UNFINISHED), np.int64)
    for stage in ("coarse", "fine"):
        if stage == "coarse":
            r = np.asarray(r_coarse, float)
        else:
            r = refinement(r_coarse, int(np.argmax(np.nan_to_num(gains[0], nan=-np.inf))), refine)
            r = r[np.isfinite(r)]
        if r.size:
            env = _envelope(setting, Omega, {**base, "omega_ratio": 1.0 / r}, r.size, signs, beta_max, tol)
            r_all.append(r)
            gains.append(env["beta_min"] / reference)
            flags.append(env["flag"])
            unknown += unfinished(env)
    r_all, gains, flags = (np.concatenate(x) for x in (r_all, gains, flags))
    order = np.argsort(r_all)
    best = order[np.argmax(np.nan_to_num(gains[order], nan=-np.inf))]
    return gains[best], r_all[best], flags[best], unknown


def threshold_tile(payload: tuple) -> dict:
    """One ``(lambda, p, Omega)``: the bare block's envelope ``beta_min`` and, for each of :data:`KINDS`, the best
    gain, its period and flag. ``payload = (setting, tunings, Omega, r_coarse, refine, signs, beta_max, tol)``."""
    setting, tunings, Omega, r_coarse, refine, signs, beta_max, tol = payload
    bare = _envelope(setting, Omega, None, 1, signs, beta_max, tol)
    out = {"bare_beta_min": bare["beta_min"], "bare_flag": bare["flag"]}
    unknown = unfinished(bare)
    reference = bare["beta_min"][0] if bare["flag"][0] == BRACKETED else np.nan
    for kind, tuning in zip(KINDS, tunings):
        gain, r, flag = np.nan, np.nan, 0
        if np.isfinite(reference):
            gain, r, flag, more = best_gain(setting, Omega, tuning, r_coarse, refine, reference, signs, beta_max, tol)
            unknown += more
        out.update({f"{kind}_gain": np.array([gain]), f"{kind}_r": np.array([r]), f"{kind}_flag": np.array([flag])})
    out.update({k: np.array([count]) for k, count in zip(UNFINISHED, unknown)})
    return out


#: Each array of a tile (:func:`threshold_tile`): the field of a threshold map's data it goes to, and the index
#: of its part there (none for the block alone's).
TILE_FIELDS = {
    "bare_beta_min": ("beta_min", ()),
    "bare_flag": ("flag", ()),
    "undetermined": ("undetermined", ()),
    **{
        f"{kind}_{f}": ("gain_flag" if f == "flag" else f, (i,))
        for i, kind in enumerate(KINDS)
        for f in ("gain", "r", "flag")
    },
}

#: The dimensions of every variable of a threshold map's data (:func:`threshold_data`), coordinates included.
DIMS = {
    **{dim: (dim,) for dim in ("part", "lam", "p", "Omega", "sign", "r_coarse")},
    "beta_max": ("lam",),
    **dict.fromkeys(("beta_min", "flag", "undetermined"), ("lam", "p", "Omega")),
    **dict.fromkeys(("gain", "r", "gain_flag"), ("part", "lam", "p", "Omega")),
}


def tile_shapes() -> dict:
    """Name -> shape of the arrays of :func:`threshold_tile`."""
    names = ("bare_beta_min", "bare_flag", *UNFINISHED, *(f"{k}_{f}" for k in KINDS for f in ("gain", "r", "flag")))
    return dict.fromkeys(names, (1,))


def threshold_map(
    lam: Grid,
    p: Grid,
    Omega: Grid,
    execution: Execution = LOCAL,
    *,
    e_ratio: float = 0.05,
    gamma: float = 0.05,
    zeta: float = 0.05,
    h: float = 0.05,
    Tm: Grid | None = None,
    refine: int = 1,
    a_max: float = A_MAX,
    tol: float = TOL,
    rtol: float = 1e-8,
    t_after: float = 15.0,
    backend: str = "c",
    directions: str = "auto",
    runs: str | Path = "out/runs",
    on_tile=None,
) -> Study:
    """``Omega*`` and the best gain over a grid of block geometries, for the unlimited damper and with stops.

    Parameters
    ----------
    lam, p : Grid
        Slenderness ``H / B`` (in [0.01, 100]) and size ``p`` (rad/s) of the blocks.
    Omega : Grid
        Pulse frequency ratios scanned at each geometry.
    execution : Execution
        Where the tiles run.
    e_ratio : float
        Eccentricity of every block, ``e / B`` (default 0.05, the reference block's).
    gamma, zeta, h : float
        The damper: mass ratio, damping ratio, height of the guide (m).
    Tm : Grid, optional
        Coarse log grid (or given values) of ``r = T_m p / (2 pi)`` searched at each point; default :data:`TM_GRID`.
    refine : int
        Refinement points each side of the best coarse period.
    a_max : float
        Bound of the ground acceleration, in g (default :data:`A_MAX`).
    tol : float
        Relative tolerance of the bisections.
    rtol, t_after, backend
        As :class:`Setting`.
    directions : {"auto", "both", "positive", "negative"}
        Signs of the pulses (:func:`rocking.study.directions.choose`).
    runs : path
        Folder of the run folders.
    on_tile : callable, optional
        Passed to :func:`rocking.study.tiles.run_tiles`.

    Returns
    -------
    Study
        ``kind = "threshold"``; its data (:func:`threshold_data`): ``beta_max`` (per ``lam``); per
        ``(lam, p, Omega)``: the block alone's ``beta_min``, ``flag`` (``ABOVE``: safe up to ``a_max``) and
        ``undetermined``; per ``(part, lam, p, Omega)`` (``part``: the dampers of :data:`KINDS`): ``gain``,
        ``r``, ``gain_flag``. ``Omega*`` and its bracket and status, the best gain and ``safe_from`` are read
        from them (:func:`thresholds`).

    Examples
    --------
    >>> import tempfile, rocking
    >>> from rocking.study.threshold import threshold_map
    >>> study = threshold_map(
    ...     rocking.Grid("lam", 4.0, 4.0, 1), rocking.Grid("p", 2.0, 2.0, 1), rocking.Grid("Omega", 4.0, 14.0, 3),
    ...     rocking.Execution(workers=1, progress=False), Tm=rocking.Grid("Tm", 0.5, 2.0, 2, log=True), refine=0,
    ...     runs=tempfile.mkdtemp())
    >>> study.data["gain"].sel(part="stops").values.round(2)  # Omega = 4, 9, 14: none at 14, safe alone to 4 g
    array([[[1.14, 1.41,  nan]]])
    >>> from rocking.study.threshold import thresholds
    >>> found = thresholds(study.data)
    >>> found["safe_from"].values, found["Omega_star_low"].sel(part="stops").values  # Omega* > 9
    (array([[14.]]), array([[9.]]))
    """
    Tm = Grid("Tm-ratio", *TM_GRID, log=True) if Tm is None else Tm
    check_study(Setting(Block.reference()), execution, runs, lam=lam, p=p, Omega=Omega, Tm=Tm)
    tol = check_tol(tol)
    if not check_real("a_max", a_max) > 0:
        raise ParameterError(f"a_max must be > 0 (a bound of the ground acceleration, in g) (got {a_max!r})")
    if not (isinstance(refine, int) and 0 <= refine <= 100):
        raise ParameterError(f"refine must be an integer in [0, 100] (got {refine!r})")
    L, P, Om, r = lam.values(), p.values(), Omega.values(), coarse_values(Tm, "T_m")
    tunings = (Tuning(gamma, zeta=zeta, h=h), Tuning(gamma, zeta=zeta, h=h, stops=True))
    blocks = [[Block.from_nondim(p=float(pj), lam=float(li), M=1000.0, e_ratio=e_ratio) for pj in P] for li in L]
    chosen = choose(directions, blocks[0][0], tunings[0])
    if directions == "auto":
        chosen["reason"] = (
            f"the blocks are eccentric (e = {e_ratio:g} B): both directions, the envelope reported"
            if e_ratio
            else chosen["reason"]
        )
    signs = chosen["signs"]
    shape = (L.size, P.size, Om.size)
    fields = {
        "beta_min": np.full(shape, np.nan),
        "flag": np.zeros(shape, int),
        "undetermined": np.zeros(shape, int),
        **{k: np.full((len(KINDS), *shape), np.nan) for k in ("gain", "r")},
        "gain_flag": np.zeros((len(KINDS), *shape), int),
    }
    grids = {
        "Omega": Omega.record(),
        "Tm_ratio": Tm.record(),
        "refine": refine,
        "beta_tol": tol,
        "a_max_g": float(a_max),
        "signs": signs,
    }
    tasks, where = [], {}
    for i, row in enumerate(blocks):
        for j, block in enumerate(row):
            setting = Setting(block, rtol=rtol, t_after=t_after, backend=backend)
            for t in tunings:
                preflight(setting, t.case_args())
            config = part_config("threshold", "block", setting, dampers=[t.record() for t in tunings], **grids)
            folder = run_folder(runs, config)
            for k, Omega_k in enumerate(Om):
                payload = (setting, tunings, float(Omega_k), r, refine, signs, beta_bound(block, a_max), tol)
                task = Task(folder / f"Omega-{k}.npz", threshold_tile, payload, tile_shapes())
                tasks.append(task)
                where[task.path] = (i, j, k)

    t_max = [0]  # not a field of the data: a run cut at t_max counts as not overturned

    def place(task: Task, tile: dict) -> None:
        i, j, k = where[task.path]
        for name, (field, index) in TILE_FIELDS.items():
            fields[field][(*index, i, j, k)] = tile[name][0]
        t_max[0] += int(tile["t_max"][0])

    # Interleave the geometries: the tiles of one differ in cost along Omega, and the progress bar stays steady.
    order = sorted(tasks, key=lambda task: (where[task.path][2], where[task.path][:2]))
    stats = run_tiles(order, place, execution, backend=backend, desc="threshold", on_tile=on_tile)
    warn_undetermined("threshold", int(fields["undetermined"].sum()))
    warn_t_max("threshold", t_max[0], t_after)
    config = {
        "kind": "threshold",
        "lam": lam.record(),
        "p": p.record(),
        "e_ratio": float(e_ratio),
        "M": 1000.0,
        "rtol": rtol,
        "t_after": t_after,
        "backend": backend,
        "dampers": [t.record() for t in tunings],
        **grids,
        "directions": chosen,
    }
    data = threshold_data(config, L, P, Om, signs, r, [beta_bound(row[0], a_max) for row in blocks], fields)
    found = thresholds(data)
    summary = {"directions": chosen, "a_max_g": float(a_max), "useless_gain": USELESS_GAIN}
    for index, kind in enumerate(KINDS):
        status = found["status"].values[index]
        summary[kind] = {name: int((status == n).sum()) for n, name in enumerate(STATUSES)}
    return Study(
        "threshold",
        config,
        data,
        summary=summary,
        run={**stats.record(), "geometries": L.size * P.size},
        tabulate=threshold_tables,
    )


def threshold_data(config: dict, lam, p, Omega, signs, r_coarse, beta_max, fields: dict):
    """A threshold map's results as labelled data: per geometry and ``Omega``, the block alone's ``beta_min``,
    ``flag`` and the responses without a verdict, and per damper (``part``: :data:`KINDS`) the best ``gain``, its
    period ``r`` and ``gain_flag``; ``beta_max`` per ``lam``."""
    import xarray as xr

    coords = {
        "part": ("part", np.array(KINDS), {"long_name": "; ".join(f"{k}: {PART_NAMES[k]}" for k in KINDS)}),
        "lam": ("lam", lam, coordinate_attrs("lam", config)),
        "p": ("p", p, coordinate_attrs("p", config)),
        "Omega": ("Omega", Omega, coordinate_attrs("Omega", config)),
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
        "r_coarse": ("r_coarse", r_coarse, coordinate_attrs("r_coarse", config)),
    }
    variables = {k: (DIMS[k], v, field_attrs(k, config)) for k, v in fields.items()}
    variables["beta_max"] = (DIMS["beta_max"], np.array(beta_max), field_attrs("beta_max", config))
    return xr.Dataset(variables, coords=coords)


def thresholds(data):
    """What a threshold map's gains give per damper and geometry (``(part, lam, p)``): ``Omega_star`` and its
    bracket ``Omega_star_low``, ``Omega_star_high`` (:func:`rocking.study.optimize.threshold_frequency`), its
    ``status`` (index into :data:`STATUSES`), the ``best_gain`` over ``Omega``; ``r_at_edge``
    (``(part, lam, p, Omega)``); and ``safe_from`` (``(lam, p)``: the lowest ``Omega`` above which the block
    alone does not overturn within the bound)."""
    import xarray as xr

    Om, gain = data["Omega"].values, data["gain"].values
    out = {}
    results = [[[threshold_frequency(Om, row) for row in plane] for plane in part] for part in gain]
    for key, name in (("Omega_star", "Omega_star"), ("low", "Omega_star_low"), ("high", "Omega_star_high")):
        values = [[[np.nan if t[key] is None else t[key] for t in row] for row in part] for part in results]
        out[name] = (("part", "lam", "p"), np.array(values), field_attrs(name, {}))
    status = [[[STATUSES.index(t["status"]) for t in row] for row in part] for part in results]
    out["status"] = (("part", "lam", "p"), np.array(status), field_attrs("status", {"kind": "threshold"}))
    gains = np.nan_to_num(gain, nan=-np.inf)
    best = np.where(np.isfinite(gains).any(axis=-1), gains.max(axis=-1), np.nan)
    out["best_gain"] = (("part", "lam", "p"), best, field_attrs("gain", {}))
    edge = at_edge(data["r"].values, data["r_coarse"].values)
    out["r_at_edge"] = (("part", "lam", "p", "Omega"), edge, field_attrs("r_at_edge", {}))
    out["safe_from"] = (("lam", "p"), safe_from(Om, data["flag"].values), field_attrs("safe_from", {}))
    return xr.Dataset(out, coords=data.drop_dims(["sign", "r_coarse"]).coords)


def safe_from(Omega, bare_flag) -> np.ndarray:
    """Per geometry, the lowest ``Omega`` from which on the block alone does not overturn within the bound
    (flag ``ABOVE`` there and at every higher ``Omega``); nan if it overturns at the last one."""
    above = np.asarray(bare_flag) == ABOVE
    # From the top down: every Omega is safe up to the last one.
    tail = np.flip(np.logical_and.accumulate(np.flip(above, axis=-1), axis=-1), axis=-1)
    first = np.argmax(tail, axis=-1)
    return np.where(tail.any(axis=-1), np.asarray(Omega)[first], np.nan)


def threshold_tables(data, config: dict) -> dict:
    """One CSV row per geometry and kind of damper: ``Omega*``, its bracket and status, the best gain."""
    found = thresholds(data)
    lam, p = np.meshgrid(data["lam"].values, data["p"].values, indexing="ij")
    names = ("Omega_star", "Omega_star_low", "Omega_star_high", "status", "best_gain")
    table: dict[str, list] = {"lam": [], "p_rad_s": [], "damper": [], **{n: [] for n in names}}
    table["bare_safe_from_Omega"] = []
    for kind in KINDS:
        a = found.sel(part=kind)
        table["lam"] += list(lam.ravel())
        table["p_rad_s"] += list(p.ravel())
        table["damper"] += [kind] * lam.size
        for name in ("Omega_star", "Omega_star_low", "Omega_star_high", "best_gain"):
            table[name] += list(a[name].values.ravel())
        table["status"] += [STATUSES[s] for s in a["status"].values.ravel()]
        table["bare_safe_from_Omega"] += list(found["safe_from"].values.ravel())
    return {"threshold": {k: np.asarray(v) for k, v in table.items()}}
