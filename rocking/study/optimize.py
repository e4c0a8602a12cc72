"""The optimal damper: for each pulse frequency, the damper period that makes overturning hardest.

The gain of a damper at the pulse frequency ratio ``Omega`` is

    G(Omega) = beta_min(with damper) / beta_min(block alone)

(:func:`rocking.study.spectrum.beta_min`); ``G > 1``: a stronger pulse is needed to
overturn the damped block. For each ``Omega`` and mass ratio ``gamma`` (given
``zeta`` and ``h``), :func:`optimize_tile` searches the damper period ``T_m``,
written ``r = T_m p / (2 pi)`` (``T_m`` in units of the block's ``2 pi / p``),
over a range (default ``r`` in [0.1, 10]).

How the search copes with a noisy, discontinuous gain
-----------------------------------------------------
``G(r)`` is not smooth: ``beta_min`` jumps when the mode of overturning
changes (after n impacts, after n + 1, without impact) or when a safe window
opens or closes below it, and it is known only to the bisection tolerance and
the resolution of the ``beta`` scan. Gradient or bracketing methods (golden
section, Brent) assume unimodality and would lock onto a local step, so:

1. *coarse scan*: ``G`` on a logarithmic grid of ``r`` over the whole range,
   every point evaluated (one vectorised :func:`~rocking.study.spectrum.beta_min`
   call for all of them); the best point ``r_k`` is a global choice among them;
2. *local refinement*: ``refine`` points, log-spaced, strictly inside each of
   the two coarse intervals next to ``r_k`` (``(r_{k-1}, r_k)`` and
   ``(r_k, r_{k+1})``): a finer scan, not a line search, so a jump inside the
   bracket cannot mislead it;
3. the optimum is the best of all points evaluated, coarse and fine; ties go
   to the shortest period (the stiffest spring, the smallest stroke).

The refinement is local: an optimum in a narrow peak that the coarse grid
misses altogether is not found, and the reported gain is the best *evaluated*
gain, a lower bound of the true maximum. Both ``beta_min`` use the same scan
grid and tolerance, so their errors are alike; gains closer to each other
than about ``2 tol`` are not distinguished.

When the damped block does not overturn anywhere in the ``beta`` scan, its
``beta_min`` exceeds the last scan amplitude: the gain is then that lower
bound (flag ``ABOVE``), which still ranks it first. Where the bare block's
``beta_min`` is not bracketed by the scan, the gain is undefined (``nan``):
widen the ``beta`` range.

The threshold frequency ``Omega*`` (:func:`threshold_frequency`) is the
frequency above which the best gain stays below 1.01: the damper is useless
there.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..model.params import ParameterError, check_in_range
from .config import Grid, Setting, Tuning, Variant, is_count, part_config
from .dataset import FIELDS, coordinate_attrs, field_attrs, si_coordinates
from .directions import beta_min_envelope, choose, repeat, sign_column
from .overturning_map import FIXED, check_study, preflight, warn_t_max, warn_undetermined
from .result import Study
from .spectrum import TOL, UNFINISHED, beta_min, check_tol, unfinished
from .tiles import LOCAL, Execution, Task, interleave, run_folder, run_tiles
from .vocabulary import ABOVE, BRACKETED, flag_words

#: Gain below which a damper is useless (the definition of Omega*).
USELESS_GAIN = 1.01

#: Default coarse grid of r = T_m p / (2 pi) (log-spaced) and refinement points per side (at most MAX_REFINE).
TM_GRID = (0.1, 10.0, 17)
REFINE = 3
MAX_REFINE = 1000

#: The dimensions of every variable of an optimisation's data (:func:`optimize_data`), coordinates included.
DIMS = {
    **{dim: (dim,) for dim in ("gamma", "Omega", "sign", "r_coarse", "gamma_or_best")},
    "T_g": ("Omega",),
    "T_m_coarse": ("r_coarse",),
    "beta_min": ("Omega", "sign"),
    "flag": ("Omega",),
    **dict.fromkeys(("gain_coarse", "flag_coarse"), ("gamma", "Omega", "r_coarse")),
    **dict.fromkeys(("r_fine", "gain_fine"), ("gamma", "Omega", "r_fine_point")),
    **dict.fromkeys(
        ("r_opt", "gain_opt", "flag_opt", "undetermined", "Tm_over_Tg_opt", "edge_opt", "k_m_opt", "c_opt"),
        ("gamma", "Omega"),
    ),
    **dict.fromkeys(("best_gain", "best_gamma", "best_r"), ("Omega",)),
    **dict.fromkeys(("Omega_star", "Omega_star_low", "Omega_star_high"), ("gamma_or_best",)),
}
#: The stages of the search a variable's name ends with, as its long name says them.
STAGES = {"coarse": "at the coarse periods", "fine": "at the refinement's periods", "opt": "at the optimal period"}
#: What the long names of the block alone's variables add: the envelope's flag is the tile's, not a reduction.
BLOCK_ALONE = {"beta_min": " (block alone)", "flag": " (block alone, of the envelope over the directions)"}


def coarse_values(grid: Grid, name: str) -> np.ndarray:
    """The values of a coarse search grid, refined between its points in log scale (:func:`refinement`):
    a logarithmic grid, or given values (:meth:`Grid.of`)."""
    if not (grid.log or grid.points):
        raise ParameterError(
            f"the coarse {name} grid must be logarithmic (Grid(..., log=True)) or given values (Grid.of)"
        )
    return grid.values()


def refinement(r_coarse, k: int, refine: int) -> np.ndarray:
    """``refine`` log-spaced points strictly inside each coarse interval next to ``r_coarse[k]``.

    Returns ``2 refine`` values; when ``r_k`` ends the grid there is one interval only,
    and the ``refine`` missing values are ``nan`` (every tile has the same shape).
    """
    r = np.asarray(r_coarse, float)
    points = [np.geomspace(r[a], r[b], refine + 2)[1:-1] for a, b in ((k - 1, k), (k, k + 1)) if 0 <= a and b < r.size]
    out = np.concatenate(points) if points else np.zeros(0)
    return np.concatenate([out, np.full(2 * refine - out.size, np.nan)])


def _envelope_beta_min(setting, Omega, beta_scan, damper, tol, signs) -> dict:
    """:func:`beta_min` of the columns of ``Omega`` (n,) and ``damper`` (arrays (n,)) in each direction of
    ``signs``, and their envelope (:func:`rocking.study.directions.beta_min_envelope`), each of shape (n,)."""
    n = np.size(Omega)
    cols = None
    if damper is not None:
        cols = {k: v if k in FIXED else repeat(np.broadcast_to(v, (n,)), signs) for k, v in damper.items()}
    res = beta_min(setting, repeat(Omega, signs), beta_scan, cols, tol=tol, sign=sign_column(n, signs))
    by_sign = {k: v.reshape(n, len(signs)) for k, v in res.items() if k != "scan_outcome"}
    return {**beta_min_envelope(by_sign), "beta_min_by_sign": by_sign["beta_min"], "t_max": by_sign["t_max"].sum(-1)}


def _gains(r, setting, Omega, damper, beta_scan, tol, reference, signs):
    """Gain (the ratio of the envelopes over ``signs``) and flag of the damped block for the periods ``r`` (nan
    where ``r`` or ``reference`` is nan), and the counts :data:`~rocking.study.spectrum.UNFINISHED` of its
    responses."""
    ok = np.isfinite(r) & np.isfinite(reference)
    gain, flag = np.full(r.shape, np.nan), np.zeros(r.shape, np.int64)
    if not ok.any():
        return gain, flag, np.zeros(len(UNFINISHED), np.int64)
    columns = {**damper, "omega_ratio": 1.0 / r[ok]}
    env = _envelope_beta_min(setting, np.full(ok.sum(), Omega), beta_scan, columns, tol, signs)
    gain[ok], flag[ok] = env["beta_min"] / reference, env["flag"]
    return gain, flag, unfinished(env)


def optimize_tile(payload: tuple) -> dict:
    """Optimal period at one ``(gamma, Omega)``: coarse scan of ``r``, refinement, best point.

    ``payload = (setting, damper, Omega, beta_scan, tol, r_coarse, refine, signs)`` with
    ``damper`` the keyword arguments ``gamma``, ``zeta``, ``h`` (and ``stops``); every
    ``beta_min`` is the envelope over the directions ``signs``.
    """
    setting, damper, Omega, beta_scan, tol, r_coarse, refine, signs = payload
    bare = _envelope_beta_min(setting, np.array([Omega]), beta_scan, None, tol, signs)
    # Only a bracketed bare beta_min is a reference; a bound would give a meaningless ratio.
    reference = bare["beta_min"][0] if bare["flag"][0] == BRACKETED else np.nan
    search = (setting, Omega, damper, beta_scan, tol, reference, signs)
    gain_coarse, flag_coarse, unknown_coarse = _gains(r_coarse, *search)
    k = int(np.argmax(np.nan_to_num(gain_coarse, nan=-np.inf)))
    r_fine = refinement(r_coarse, k, refine) if np.isfinite(reference) else np.full(2 * refine, np.nan)
    gain_fine, flag_fine, unknown_fine = _gains(r_fine, *search)
    r_all = np.concatenate([r_coarse, r_fine])
    gain_all = np.concatenate([gain_coarse, gain_fine])
    flag_all = np.concatenate([flag_coarse, flag_fine])
    order = np.argsort(r_all)  # nan last; argmax then takes the shortest period among ties
    best = order[np.argmax(np.nan_to_num(gain_all[order], nan=-np.inf))]
    found = np.isfinite(gain_all[best])
    return {
        "bare_beta_min": bare["beta_min"],
        "bare_beta_min_by_sign": bare["beta_min_by_sign"][0],
        "bare_flag": bare["flag"],
        "gain_coarse": gain_coarse,
        "flag_coarse": flag_coarse,
        "r_fine": r_fine,
        "gain_fine": gain_fine,
        "r_opt": np.array([r_all[best] if found else np.nan]),
        "gain_opt": np.array([gain_all[best]]),
        "flag_opt": np.array([flag_all[best]]),
        **{k: np.array([n]) for k, n in zip(UNFINISHED, unfinished(bare) + unknown_coarse + unknown_fine)},
    }


def tile_arrays(n_coarse: int, refine: int, n_signs: int) -> dict:
    """Name -> shape of the arrays of :func:`optimize_tile` (``n_coarse`` coarse periods, ``n_signs``
    directions)."""
    shapes = dict.fromkeys(("bare_beta_min", "bare_flag", "r_opt", "gain_opt", "flag_opt", *UNFINISHED), (1,))
    shapes["bare_beta_min_by_sign"] = (n_signs,)
    shapes.update(dict.fromkeys(("gain_coarse", "flag_coarse"), (n_coarse,)))
    shapes.update(dict.fromkeys(("r_fine", "gain_fine"), (2 * refine,)))
    return shapes


def at_edge(r_opt, r_coarse) -> np.ndarray:
    """-1 where the optimum is the shortest period of the search range, +1 the longest, 0 inside (or none):
    an optimum at an edge may lie beyond it (widen ``Tm``)."""
    r_opt = np.asarray(r_opt, float)
    return np.where(r_opt == r_coarse[0], -1, np.where(r_opt == r_coarse[-1], 1, 0))


def warn_at_edge(edge, r_coarse) -> None:
    """Warn where the optimal period (``edge``: :func:`at_edge` of each optimum) is an end of its search range
    ``r_coarse``: the best may lie beyond it."""
    low, high = int((edge < 0).sum()), int((edge > 0).sum())
    if low + high:
        warnings.warn(
            f"optimize: the optimal T_m p / 2 pi is an end of its search range at {low + high} of {edge.size} "
            f"(gamma, Omega) points ({low} at the smallest, {r_coarse[0]:.3g}; {high} at the largest, "
            f"{r_coarse[-1]:.3g}): the best may lie beyond; widen the range (Tm_ratio / --Tm-ratio MIN MAX N)",
            EdgeWarning,
            stacklevel=3,
        )


class EdgeWarning(UserWarning):
    """An optimum of a search is an end of its search range: the best may lie beyond."""


def threshold_frequency(Omega, gain, level: float = USELESS_GAIN) -> dict:
    """``Omega*``: above it the gain stays below ``level``; with the scanned bracket around it.

    Only frequencies where the gain is defined count (``nan``: the bare block's
    ``beta_min`` is outside the ``beta`` scan); the bracket is made of two of them.

    Parameters
    ----------
    Omega : array_like
        Increasing frequency ratios.
    gain : array_like
        Best gain at each.
    level : float
        Gain that counts as useful.

    Returns
    -------
    dict
        ``Omega_star`` (linear interpolation of the gain across ``level``
        inside the bracket), ``low`` and ``high`` (the two scanned values
        around it), ``status``: ``"bracketed"``, ``"below_range"`` (the gain
        is below ``level`` everywhere: ``Omega* <= high``), ``"above_range"``
        (useful at the last defined frequency: ``Omega* > low``) or
        ``"undefined"``; ``defined_up_to``: the last frequency with a defined
        gain. Values that are not known are ``None``.
    """
    Omega, gain = np.asarray(Omega, float), np.asarray(gain, float)
    defined = np.isfinite(gain)
    out = {"Omega_star": None, "low": None, "high": None, "status": "undefined", "defined_up_to": None}
    if not defined.any():
        return out
    Omega, gain = Omega[defined], gain[defined]
    out["defined_up_to"] = float(Omega[-1])
    useful = np.flatnonzero(gain >= level)
    if useful.size == 0:
        return {**out, "high": float(Omega[0]), "status": "below_range"}
    i = useful[-1]
    if i == Omega.size - 1:
        return {**out, "low": float(Omega[-1]), "status": "above_range"}
    lo, hi, g_lo, g_hi = Omega[i], Omega[i + 1], gain[i], gain[i + 1]
    star = lo + (hi - lo) * (g_lo - level) / (g_lo - g_hi)
    return {**out, "Omega_star": float(star), "low": float(lo), "high": float(hi), "status": "bracketed"}


def _iterable(values) -> tuple:
    try:
        return tuple(values)
    except TypeError:
        return ()


def check_gammas(gammas, name: str = "gammas") -> tuple[float, ...]:
    """Mass ratios, validated: a non-empty list of distinct numbers in the range of :class:`Tuning`'s ``gamma``.

    ``name``: the parameter as the user gave it (``--gammas`` on the command line). A repeated value is refused
    here: each mass ratio labels its results (``f"{gamma:g}"``), and the study would fail only after all its work.
    """
    gammas = _iterable(gammas)
    if not gammas:
        raise ParameterError(f"{name} must list at least one mass ratio m/M")
    checked = tuple(check_in_range("gamma", g, nonzero=True) for g in gammas)
    labels = [f"{g:g}" for g in checked]
    repeated = [label for i, label in enumerate(labels) if label in labels[:i]]
    if repeated:
        raise ParameterError(
            f"{name} must list distinct mass ratios m/M, to 6 significant digits (got {repeated[0]} more than once)"
        )
    return checked


def optimal_damper(
    setting: Setting,
    gammas,
    Omega: Grid,
    beta: Grid,
    execution: Execution = LOCAL,
    *,
    zeta: float = 0.05,
    h: float = 0.05,
    stops: bool = False,
    Tm: Grid | None = None,
    refine: int = REFINE,
    tol: float = TOL,
    runs: str | Path = "out/runs",
    directions: str = "auto",
    on_tile=None,
) -> Study:
    """Optimal damper period and best gain against ``Omega`` for each mass ratio in ``gammas``; the gain is
    the ratio of the envelopes of ``beta_min`` over the directions of the pulse.

    Parameters
    ----------
    setting : Setting
        Block and solver.
    gammas : sequence of float
        Mass ratios; the best over them is reported too (a search in ``gamma``).
    Omega : Grid
        Pulse frequency ratios (increasing).
    beta : Grid
        Scan amplitudes of every ``beta_min``.
    execution : Execution
        Where the tiles run.
    zeta, h : float
        Damping ratio and guide height (m) of the damper.
    stops : bool
        The guide ends in the stops of :meth:`rocking.Stops.at_edges` (as :class:`Tuning`).
    Tm : Grid, optional
        Coarse grid of ``r = T_m p / (2 pi)``, log-spaced or given values (:func:`coarse_values`); default
        :data:`TM_GRID`.
    refine : int
        Refinement points on each side of the best coarse point (>= 0).
    tol : float
        Relative tolerance of the bisections.
    runs : path
        Folder of the run folders.
    directions : {"auto", "both", "positive", "negative"}
        Signs of the pulses (:func:`rocking.study.directions.choose`): ``"auto"`` runs both unless the block
        is symmetric.
    on_tile : callable, optional
        Passed to :func:`rocking.study.tiles.run_tiles`.

    Returns
    -------
    Study
        ``kind = "optimize"``; its data (:func:`optimize_data`, dimensions :data:`DIMS`): the block alone's
        ``beta_min`` per ``(Omega, sign)`` (its envelope: :func:`bare_beta_min`) and the ``flag`` of that envelope;
        per ``(gamma, Omega)``: ``r_opt``, ``Tm_over_Tg_opt`` (``T_m / T_g``, ``T_g = 2 pi / omega_g``),
        ``gain_opt``, ``flag_opt``, ``edge_opt`` (:func:`at_edge`), ``k_m_opt`` and ``c_opt`` (the damper's
        spring, N/m, and dashpot, N s/m), ``undetermined`` (responses without a verdict, counted as not
        overturned); per ``(gamma, Omega, r_coarse)``: ``gain_coarse``, ``flag_coarse``; the refinement's
        ``r_fine``, ``gain_fine``; the best over ``gamma``: ``best_gain``, ``best_gamma``, ``best_r``;
        ``Omega_star`` and its bracket per ``gamma_or_best`` (each ``gamma``, then the best; ``nan`` if not
        bracketed).

    Raises
    ------
    ParameterError
        Naming the parameter and its valid range, before any work: inputs of
        the wrong type, more than :data:`rocking.study.config.MAX_CELLS`
        cells, a folder that cannot be written, a back end or a Dask cluster
        that cannot be used.
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
    EdgeWarning
        For optimal periods at an end of their search range (:func:`warn_at_edge`).

    Examples
    --------
    >>> import tempfile, rocking
    >>> from rocking.study.optimize import optimal_damper
    >>> study = optimal_damper(
    ...     rocking.Setting(rocking.Block.reference()), [0.05],
    ...     rocking.Grid("Omega", 4.0, 6.0, 2), rocking.Grid("beta", 0.5, 15.0, 30),
    ...     rocking.Execution(workers=1, progress=False),
    ...     Tm=rocking.Grid("Tm", 0.5, 2.0, 3, log=True), refine=1, runs=tempfile.mkdtemp())
    >>> study.data["r_opt"].values.round(3), study.data["best_gain"].values.round(2)  # T_m p / 2 pi, and its gain
    (array([[1.414, 1.414]]), array([1.12, 1.41]))
    """
    if isinstance(gammas, (Tuning, Variant)) or any(isinstance(g, (Tuning, Variant)) for g in _iterable(gammas)):
        raise ParameterError(
            "optimal_damper searches the period T_m of the paper's omd damper: give mass ratios gammas, "
            "not a Tuning or a Variant (a Variant's parameters are fixed; run overturning_map or "
            "minimum_overturning_spectrum for it)"
        )
    Tm = Grid("Tm-ratio", *TM_GRID, log=True) if Tm is None else Tm
    check_study(setting, execution, runs, Omega=Omega, beta=beta, Tm=Tm)
    gammas = check_gammas(gammas)
    tol = check_tol(tol)
    if not (is_count(refine) and 0 <= refine <= MAX_REFINE):
        raise ParameterError(f"refine must be an integer in [0, {MAX_REFINE}] (got {refine!r})")
    refine = int(refine)
    r = coarse_values(Tm, "T_m")
    zeta, h = check_in_range("zeta", zeta), check_in_range("h", h)
    if not isinstance(stops, (bool, np.bool_)):
        raise ParameterError(f"stops must be True or False (got {stops!r})")
    chosen = choose(directions, setting.block)
    signs = chosen["signs"]
    Om, b = Omega.values(), beta.values()
    nG, nO, nr = len(gammas), Om.size, r.size
    grids = {"Omega": Omega.record(), "beta": beta.record(), "beta_tol": tol, "Tm_ratio": Tm.record(), "refine": refine}
    grids["signs"] = signs
    fields = {
        "beta_min": np.full((nO, len(signs)), np.nan),
        "flag": np.zeros(nO, np.int64),
        "gain_coarse": np.full((nG, nO, nr), np.nan),
        "flag_coarse": np.zeros((nG, nO, nr), np.int64),
        "r_fine": np.full((nG, nO, 2 * refine), np.nan),
        "gain_fine": np.full((nG, nO, 2 * refine), np.nan),
        "r_opt": np.full((nG, nO), np.nan),
        "gain_opt": np.full((nG, nO), np.nan),
        "flag_opt": np.zeros((nG, nO), np.int64),
        "undetermined": np.zeros((nG, nO), np.int64),
    }
    groups, where, folders = [], {}, {}
    for g, gamma in enumerate(gammas):
        damper = {"gamma": gamma, "zeta": float(zeta), "h": float(h), **({"stops": True} if stops else {})}
        folder = run_folder(runs, part_config("optimize", f"gamma{gamma:g}", setting, damper=damper, **grids))
        folders[f"{gamma:g}"] = folder.name
        part_tasks: list[Task] = []
        groups.append(part_tasks)
        for i, Omega_i in enumerate(Om):
            payload = (setting, damper, float(Omega_i), b, tol, r, refine, signs)
            task = Task(folder / f"Omega-{i}.npz", optimize_tile, payload, tile_arrays(nr, refine, len(signs)))
            part_tasks.append(task)
            where[task.path] = (g, i)

    t_max = [0]  # not a field of the data: a run cut at t_max counts as not overturned

    def place(task: Task, res: dict) -> None:
        g, i = where[task.path]
        t_max[0] += int(res["t_max"][0])
        # A tile gives the block alone's beta_min per direction but only its envelope's flag: the envelope's
        # beta_min is a reduction over sign (bare_beta_min).
        fields["beta_min"][i], fields["flag"][i] = res["bare_beta_min_by_sign"], res["bare_flag"][0]
        for k in ("gain_coarse", "flag_coarse", "r_fine", "gain_fine"):
            fields[k][g, i] = res[k]
        for k in ("r_opt", "gain_opt", "flag_opt", "undetermined"):
            fields[k][g, i] = res[k][0]

    preflight(setting)
    stats = run_tiles(interleave(*groups), place, execution, backend=setting.backend, desc="optimize", on_tile=on_tile)
    warn_undetermined("optimize", int(fields["undetermined"].sum()))
    warn_t_max("optimize", t_max[0], setting.t_after)
    fields["Tm_over_Tg_opt"] = fields["r_opt"] * Om  # T_m / T_g = (T_m p / 2 pi) (omega_g / p)
    fields["edge_opt"] = at_edge(fields["r_opt"], r)
    warn_at_edge(fields["edge_opt"], r)
    m = np.array(gammas)[:, None] * setting.block.M
    omega_m = setting.block.p / fields["r_opt"]
    fields["k_m_opt"], fields["c_opt"] = m * omega_m**2, 2 * zeta * m * omega_m
    best = np.argmax(np.nan_to_num(fields["gain_opt"], nan=-np.inf), axis=0)
    cols = np.arange(nO)
    fields["best_gain"] = fields["gain_opt"][best, cols]
    fields["best_gamma"] = np.where(np.isfinite(fields["best_gain"]), np.array(gammas)[best], np.nan)
    fields["best_r"] = fields["r_opt"][best, cols]
    thresholds = {f"{gamma:g}": threshold_frequency(Om, fields["gain_opt"][g]) for g, gamma in enumerate(gammas)}
    thresholds["best"] = threshold_frequency(Om, fields["best_gain"])
    for key, name in (("Omega_star", "Omega_star"), ("low", "Omega_star_low"), ("high", "Omega_star_high")):
        fields[name] = np.array([np.nan if t[key] is None else t[key] for t in thresholds.values()])
    config = {"kind": "optimize", **setting.record(), "gammas": list(gammas), "zeta": zeta, "h": h, **grids}
    config["directions"] = chosen
    if stops:
        config["stops"] = True
    return Study(
        "optimize",
        config,
        optimize_data(config, Om, gammas, signs, r, fields),
        summary={
            "useless_gain": USELESS_GAIN,
            "Omega_star": thresholds,
            "undetermined": int(fields["undetermined"].sum()),
            "optima_at_edge": int((fields["edge_opt"] != 0).sum()),
            "directions": chosen,
        },
        run={**stats.record(), "run_folders": folders},
        tabulate=optimize_tables,
    )


def optimize_data(config: dict, Omega, gammas, signs, r_coarse, fields: dict):
    """An optimisation's results as labelled data (:data:`DIMS`), with the coordinates in non-dimensional and SI
    terms and units; ``gamma_or_best`` labels the thresholds of each mass ratio and of the best over them."""
    import xarray as xr

    labels = [f"{g:g}" for g in gammas] + ["best"]
    coords = {
        "gamma": ("gamma", np.array(gammas), coordinate_attrs("gamma", config)),
        "Omega": ("Omega", Omega, coordinate_attrs("Omega", config)),
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
        "r_coarse": ("r_coarse", r_coarse, coordinate_attrs("r_coarse", config)),
        "gamma_or_best": ("gamma_or_best", np.array(labels), {"long_name": "mass ratio m / M, or the best"}),
    }
    coords.update(si_coordinates(config, coords))
    return xr.Dataset({k: (DIMS[k], v, _attrs(k, config)) for k, v in fields.items()}, coords=coords)


def _attrs(name: str, config: dict) -> dict:
    """Units and meaning of the variable ``name`` of an optimisation's data: those of its field (``gain_opt``:
    ``gain``), said of the block alone, of a stage of the search (:data:`STAGES`) or of the best mass ratio."""
    base, _, stage = name.rpartition("_")
    if name in FIELDS or stage not in STAGES:
        field = name if name in FIELDS else name.removeprefix("best_")
        attrs = field_attrs(field, config)
        note = ", of the best mass ratio" if field != name else BLOCK_ALONE.get(name, "")
    else:
        attrs = field_attrs("gain_flag" if base == "flag" else base, config)
        note = f", {STAGES[stage]}"
    attrs["long_name"] += note
    return attrs


def bare_beta_min(data):
    """The block alone's ``beta_min`` at each ``Omega`` in an optimisation's data: the envelope over the
    directions, their smaller one (:func:`rocking.study.directions.beta_min_envelope`)."""
    return data["beta_min"].min("sign", skipna=False)


def optimize_tables(data, config: dict) -> dict:
    """The table of an optimisation (:func:`optimize_table`)."""
    return {"optimize": optimize_table(data)}


def optimize_table(data) -> dict:
    """One CSV row per ``(gamma, Omega)``: the optimal period (both ways of writing it, and whether it is
    an edge of the search range: -1 the shortest, +1 the longest), the damper in SI units, and the gain."""
    G, Om = np.meshgrid(data["gamma"].values, data["Omega"].values, indexing="ij")
    a = {k: data[k].values for k in ("r_opt", "Tm_over_Tg_opt", "gain_opt", "flag_opt", "edge_opt", "k_m_opt", "c_opt")}
    return {
        "gamma": G.ravel(),
        "Omega": Om.ravel(),
        "bare_beta_min": np.broadcast_to(bare_beta_min(data).values, G.shape).ravel(),
        "bare_beta_min_is": flag_words(np.broadcast_to(data["flag"].values, G.shape).ravel()),
        "Tm_p_over_2pi_opt": a["r_opt"].ravel(),
        "Tm_over_Tg_opt": a["Tm_over_Tg_opt"].ravel(),
        "gain_opt": a["gain_opt"].ravel(),
        "gain_lower_bound": (a["flag_opt"] == ABOVE).ravel(),
        "Tm_at_edge": a["edge_opt"].ravel(),
        "k_m_opt_N_per_m": a["k_m_opt"].ravel(),
        "c_opt_N_s_per_m": a["c_opt"].ravel(),
    }
