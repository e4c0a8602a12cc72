"""The design answer: one damper, with its stops, for a band of pulses and both directions.

For a block, a band of one-sine pulse frequency ratios ``Omega`` (pulses of both
signs when the block is not symmetric, :mod:`rocking.study.directions`), a mass
budget ``gamma = m / M`` and a stroke (stops at ``x = +-L``), :func:`design`
finds the damper period ``T_m`` (written ``r = T_m p / (2 pi)``) and damping
ratio ``zeta`` that maximise the *worst gain over the band*:

    G_worst(r, zeta) = min over Omega of G(Omega),
    G(Omega) = beta_min(with the damper) / beta_min(block alone),

each ``beta_min`` the envelope over the directions (the smaller of the two).
The damper's whole mass budget is used.

The search is that of :mod:`rocking.study.optimize`, in two parameters: every
point of a coarse grid of ``r`` (log) x ``zeta`` (log) is evaluated (one tile
each: ``beta_min`` of every ``Omega`` and direction in one call), then
``refine`` log-spaced points inside the coarse intervals next to the best point,
along ``r`` at its ``zeta`` and along ``zeta`` at its ``r``. The optimum is the
best point evaluated (a lower bound of the true maximum; ties go to the
shorter period, then the smaller damping). An optimum on an edge of the coarse
grid is flagged: the best damper may lie beyond it.

The damper must be buildable: its mass must stay on the block (``|x| <= B/2``,
the stop's pad not crushed) under the *design pulses*, those that just overturn
the block alone (its envelope ``beta_min`` at each ``Omega``, both directions).
Every candidate is run there too, and the optimum is the best candidate that
keeps its mass on the block (the best of all, flagged, if none does). Its
*stroke use* there is reported: the largest ``|x| / L``, the stop contacts and
the largest bumper force.

What the design achieved is its *verdict* (:data:`VERDICTS`, :func:`verdict`): a code and its sentence, in the
summary and the Dataset's attributes; a design that does not help warns a :class:`DesignWarning`, an optimum at an
end of its search range an :class:`~rocking.study.optimize.EdgeWarning` (the command line prints the same).

Units SI (m, kg, s, N); the pulse parameters are non-dimensional.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np

from ..model.params import (
    BUMPER_DEPTH,
    Damper,
    ParameterError,
    Stops,
    check_in_range,
    check_interval,
    edge_stops,
)
from .config import Grid, Setting, is_count, part_config
from .dataset import coordinate_attrs, field_attrs, si_coordinates
from .directions import SIGN_NAMES, beta_min_envelope, choose, repeat, sign_column, study_data
from .ida import _user_stacklevel
from .optimize import MAX_REFINE, USELESS_GAIN, EdgeWarning, at_edge, coarse_values, refinement
from .overturning_map import PARTS, check_study, preflight, respond, warn_t_max, warn_undetermined
from .result import Study
from .spectrum import COLUMN_FIELDS, TOL, beta_min, censored, check_tol
from .tiles import LOCAL, Execution, Task, run_folder, run_tiles
from .vocabulary import ABOVE, BRACKETED, PART_NAMES, flag_words

#: Default coarse grids: r = T_m p / (2 pi) and zeta (both log-spaced), and refinement points per side.
TM_GRID = (0.1, 10.0, 13)
ZETA_GRID = (0.02, 0.5, 5)
REFINE = 2

#: What a design achieved, by code: the sentence each code opens with (:func:`verdict` completes it). A worst gain
#: above :data:`rocking.study.optimize.USELESS_GAIN` (the threshold of ``Omega*``) helps.
VERDICTS = {
    "helps": "helps",
    "no_useful_gain": "no useful gain",
    "harms": "makes some pulses worse",
    "undefined": "no verdict",
}


class DesignWarning(UserWarning):
    """The damper designed does not help over its band: it makes some pulses worse, gains nothing useful, or has no
    verdict (the gain is undefined over the whole band); the verdict (:func:`verdict`) says which."""


#: Arrays of :func:`band_tile`, each ``(nOmega, nsigns)``: the ``beta_min`` results, and the stroke at the
#: design pulses.
BAND_FIELDS = (
    *("beta_min", "beta_safe", "flag", "impacts", "undetermined", "t_max"),
    *("x_max", "stop_contacts", "bumper_force_max"),
)

#: The dimensions of every variable of a design's data (:func:`design_data`), coordinates included.
DIMS = {
    **{dim: (dim,) for dim in ("part", "Omega", "sign", "r_coarse", "zeta_coarse")},
    "T_g": ("Omega",),
    "T_m_coarse": ("r_coarse",),
    **dict.fromkeys(COLUMN_FIELDS, ("part", "Omega", "sign")),
    **dict.fromkeys(("stroke_use", "stop_contacts", "bumper_force_max"), ("Omega", "sign")),
    **dict.fromkeys(("gain_opt", "flag_opt"), ("Omega",)),
    **dict.fromkeys(("candidate_r", "candidate_zeta", "candidate_worst_gain", "candidate_on_block"), ("candidate",)),
    "candidate_gain": ("candidate", "Omega"),
}
#: What the long names of the design's own variables add to their field's.
NOTES = {
    **dict.fromkeys(
        ("stroke_use", "stop_contacts", "bumper_force_max"),
        ", of the design at the pulses that overturn the block alone (its beta_min), per direction",
    ),
    **dict.fromkeys(("gain_opt", "flag_opt"), ", of the design, over the band"),
}


def band_tile(payload: tuple) -> dict:
    """One damper over the band, every direction: ``(setting, damper_or_None, Omega, beta_scan, tol, signs,
    design_beta)`` -> :data:`BAND_FIELDS`.

    ``design_beta`` (nOmega,): the pulses at which the stroke is measured (the bare block's ``beta_min``;
    nan: none, and for the bare block itself).
    """
    setting, damper, Omega, beta_scan, tol, signs, design_beta = payload
    n, ns = len(Omega), len(signs)
    res = beta_min(setting, repeat(Omega, signs), beta_scan, damper, tol=tol, sign=sign_column(n, signs))
    out = {k: res[k].reshape(n, ns) for k in BAND_FIELDS[:6]}
    out.update(stroke_at(setting, damper, Omega, design_beta, signs))
    return out


def stroke_at(setting: Setting, damper: dict | None, Omega, beta, signs) -> dict:
    """``x_max`` (m), ``stop_contacts`` and ``bumper_force_max`` (N) of the responses to ``(Omega, beta)`` in
    every direction, each ``(nOmega, nsigns)``; nan and 0 where ``beta`` is nan (or for the bare block)."""
    shape = (np.size(Omega), len(signs))
    out = {
        "x_max": np.full(shape, np.nan),
        "stop_contacts": np.zeros(shape, np.int64),
        "bumper_force_max": np.full(shape, np.nan),
    }
    ok = np.isfinite(beta)
    if damper is not None and ok.any():
        res = respond(setting, np.asarray(Omega)[ok, None], np.asarray(beta)[ok, None], damper, np.array(signs)[None])
        for k in out:
            out[k][ok] = res[k]
    return out


def band_gain(damped: dict, reference) -> tuple[np.ndarray, np.ndarray]:
    """The gain over the band (ratio of the envelopes; nan where the bare ``beta_min`` is not bracketed) and
    the flag of the damped envelope (:data:`rocking.study.vocabulary.ABOVE`: the gain is a lower bound)."""
    env = beta_min_envelope(damped)
    return env["beta_min"] / reference, env["flag"]


def worst_gain(gain) -> float:
    """The smallest gain over the band where it is defined; nan if nowhere."""
    gain = np.asarray(gain, float)
    return float(np.nanmin(gain)) if np.isfinite(gain).any() else np.nan


def best_candidate(r, zeta, worst, admissible) -> int:
    """Index of the largest worst gain among the ``admissible`` candidates (all, if none is); ties to the
    shorter period, then the smaller damping."""
    admissible = np.asarray(admissible, bool)
    score = np.where(admissible | ~admissible.any(), np.nan_to_num(np.asarray(worst, float), nan=-np.inf), -np.inf)
    order = np.lexsort((zeta, r))
    return int(order[np.argmax(score[order])])


def design(
    setting: Setting,
    Omega: Grid,
    beta: Grid,
    execution: Execution = LOCAL,
    *,
    gamma: float = 0.05,
    stroke: float | None = None,
    h: float = 0.05,
    Tm: Grid | None = None,
    zeta: Grid | None = None,
    refine: int = REFINE,
    tol: float = TOL,
    directions: str = "auto",
    runs: str | Path = "out/runs",
    on_tile=None,
) -> Study:
    """The damper with stops that maximises the worst gain over a band of pulses and both directions.

    Parameters
    ----------
    setting : Setting
        Block and solver.
    Omega : Grid
        The band of pulse frequency ratios the damper must serve.
    beta : Grid
        Scan amplitudes of every ``beta_min``; the bare block's must be bracketed over the band.
    execution : Execution
        Where the tiles run.
    gamma : float
        Mass budget ``m / M``, in [1e-10, 10]; the damper's mass is ``gamma M``.
    stroke : float, optional
        Half-stroke ``L`` of the stops, m, in ``(0, B/2)``. Default ``B/2`` minus the pads' depth
        (:data:`rocking.model.params.BUMPER_DEPTH`); the bumpers are those of :meth:`rocking.Stops.at_edges`.
    h : float
        Height of the guide above the top of the block, m.
    Tm, zeta : Grid, optional
        Coarse log grids (or given values, :meth:`Grid.of`) of ``r = T_m p / (2 pi)`` and of the damping
        ratio, refined between their points in log scale; defaults :data:`TM_GRID`,
        :data:`ZETA_GRID`.
    refine : int
        Refinement points each side of the best coarse point, along each parameter (>= 0).
    tol : float
        Relative tolerance of the bisections.
    directions : {"auto", "both", "positive", "negative"}
        Signs of the pulses (:func:`rocking.study.directions.choose`).
    runs : path
        Folder of the run folders.
    on_tile : callable, optional
        Passed to :func:`rocking.study.tiles.run_tiles`.

    Returns
    -------
    Study
        ``kind = "design"``; its data (:func:`design_data`, dimensions :data:`DIMS`): per ``(part, Omega,
        sign)`` (``part``: the block alone and with the design) the ``beta_min`` results (their envelope over
        the directions: :func:`envelope`); every candidate evaluated (coarse first): ``candidate_r``,
        ``candidate_zeta``, ``candidate_gain`` (over the band), ``candidate_worst_gain``, ``candidate_on_block``;
        the design: ``gain_opt`` and ``flag_opt`` (over the band), and per ``(Omega, sign)`` at the block
        alone's ``beta_min`` (the design pulses): ``stroke_use`` (largest ``|x| / L``; over the directions:
        :func:`stroke_use`), ``stop_contacts``,
        ``bumper_force_max`` (N). The summary gives the damper in SI units (``m``, ``k_m``, ``c``,
        ``T_m``, ``L``, ``k_b``, ``c_b``) and non-dimensionally (``gamma``, ``Tm_ratio``, ``zeta``),
        the worst gain and where, the edge flags and the ``verdict`` (:func:`verdict`). The damper built, with its
        stops, for :func:`rocking.simulate` and every study: :func:`designed_damper`.

    Warns
    -----
    DesignWarning
        The design does not help over the band (its verdict is not ``"helps"``).
    rocking.study.optimize.EdgeWarning
        The optimal ``T_m p / (2 pi)`` or ``zeta`` is an end of its search range.

    Raises
    ------
    ParameterError
        Naming the parameter and its valid range, before any work.
    rocking.study.tiles.Interrupted
        On Ctrl-C: the finished tiles are kept in ``runs``, and the same call resumes from them.

    Examples
    --------
    >>> import tempfile, rocking
    >>> from rocking.study.design import design
    >>> study = design(
    ...     rocking.Setting(rocking.Block.reference()), rocking.Grid("Omega", 4.0, 6.0, 2),
    ...     rocking.Grid("beta", 0.5, 20.0, 27), rocking.Execution(workers=1, progress=False),
    ...     Tm=rocking.Grid("Tm", 0.5, 4.0, 3, log=True), zeta=rocking.Grid("zeta", 0.02, 0.2, 2, log=True),
    ...     refine=1, runs=tempfile.mkdtemp())
    >>> d = study.summary["damper"]
    >>> round(d["m_kg"]), round(d["k_m_N_per_m"], 1), round(d["c_N_s_per_m"], 1)  # kg, N/m, N s/m
    (50, 22.3, 1.3)
    >>> round(study.summary["worst_gain"], 2), study.summary["zeta_at_edge"]  # -1: the smallest zeta tried
    (1.15, -1)
    """
    Tm = Grid("Tm-ratio", *TM_GRID, log=True) if Tm is None else Tm
    zeta = Grid("zeta", *ZETA_GRID, log=True) if zeta is None else zeta
    check_study(setting, execution, runs, Omega=Omega, beta=beta, Tm=Tm, zeta=zeta)
    r_grid, z_grid = coarse_values(Tm, "T_m"), coarse_values(zeta, "zeta")
    for z in z_grid[[0, -1]]:
        check_in_range("zeta", z)
    gamma, h, tol = check_in_range("gamma", gamma, nonzero=True), check_in_range("h", h), check_tol(tol)
    block = setting.block
    L = (
        block.B / 2 - BUMPER_DEPTH
        if stroke is None
        else check_interval("stroke", stroke, 0.0, block.B / 2, "m", label="(0, B/2)")
    )
    if not L > 0:
        raise ParameterError(f"the block (B = {block.B:g} m) is narrower than the pads: give stroke in (0, B/2)")
    if not (is_count(refine) and 0 <= refine <= MAX_REFINE):
        raise ParameterError(f"refine must be an integer in [0, {MAX_REFINE}] (got {refine!r})")
    chosen = choose(directions, block)
    signs = chosen["signs"]
    Om, b = Omega.values(), beta.values()
    fixed = {"gamma": gamma, "h": h, "stops": True, "stroke": L}
    grids = {"Omega": Omega.record(), "beta": beta.record(), "beta_tol": tol, "signs": signs}
    preflight(setting, {**fixed, "omega_ratio": 1.0 / r_grid[0], "zeta": float(z_grid[0])})
    folders = {"bare": run_folder(runs, part_config("design", "bare", setting, damper=None, **grids))}
    tiles: dict[tuple, dict] = {}
    stats = []

    def evaluate(points, design_beta) -> None:
        """Run the tiles of the candidates ``points`` ((r, zeta) pairs; ``None``: the bare block) not yet run."""
        tasks, where = [], {}
        for point in dict.fromkeys(points):
            if point in tiles:
                continue
            if point is None:
                damper, path = None, folders["bare"] / "bare.npz"
            else:
                damper = {**fixed, "omega_ratio": 1.0 / point[0], "zeta": point[1]}
                path = folders["damper"] / f"r{point[0]:.17g}-zeta{point[1]:.17g}.npz"
            expect = dict.fromkeys(BAND_FIELDS, (Om.size, len(signs)))
            tasks.append(Task(path, band_tile, (setting, damper, Om, b, tol, signs, design_beta), expect))
            tiles[point], where[path] = {}, point

        def place(task: Task, arrays: dict) -> None:
            tiles[where[task.path]].update(arrays)

        stats.append(run_tiles(tasks, place, execution, backend=setting.backend, desc="design", on_tile=on_tile))

    evaluate([None], np.full(Om.size, np.nan))
    bare = beta_min_envelope({k: tiles[None][k] for k in BAND_FIELDS[:5]})
    reference = np.where(bare["flag"] == BRACKETED, bare["beta_min"], np.nan)
    if not np.isfinite(reference).any():
        raise ParameterError(
            "the block alone does not overturn within the beta scan at any Omega of the band: widen beta"
        )
    folders["damper"] = run_folder(
        runs,
        part_config(
            "design", "damper", setting, damper=fixed, **grids, design_beta=[float(x) for x in bare["beta_min"]]
        ),
    )

    def judged(points) -> tuple[np.ndarray, np.ndarray]:
        """The worst gain over the band of each candidate, and whether its mass stays on the block."""
        worst = np.array([worst_gain(band_gain(tiles[p], reference)[0]) for p in points])
        on_block = np.array([np.nanmax(tiles[p]["x_max"], initial=0.0) <= block.B / 2 for p in points])
        return worst, on_block

    coarse = [(float(r), float(z)) for z in z_grid for r in r_grid]
    evaluate(coarse, bare["beta_min"])
    r_best, z_best = coarse[best_candidate(*np.array(coarse).T, *judged(coarse))]
    fine = [(float(r), z_best) for r in refinement(r_grid, int(np.flatnonzero(r_grid == r_best)[0]), refine)]
    fine += [(r_best, float(z)) for z in refinement(z_grid, int(np.flatnonzero(z_grid == z_best)[0]), refine)]
    fine = [p for p in fine if np.isfinite(p).all()]
    evaluate(fine, bare["beta_min"])
    points = list(dict.fromkeys([*coarse, *fine]))
    worst, on_block = judged(points)
    r_all, z_all = np.array(points).T
    best = points[best_candidate(r_all, z_all, worst, on_block)]
    fields = {k: np.stack([tiles[None][k], tiles[best][k]]) for k in COLUMN_FIELDS}
    # The stroke at the design pulses, of the design only (the block alone has none).
    fields["stroke_use"] = tiles[best]["x_max"] / L
    fields.update({k: tiles[best][k] for k in ("stop_contacts", "bumper_force_max")})
    fields["gain_opt"], fields["flag_opt"] = band_gain(tiles[best], reference)
    fields["candidate_r"], fields["candidate_zeta"] = r_all, z_all
    fields["candidate_gain"] = np.array([band_gain(tiles[p], reference)[0] for p in points])
    fields["candidate_worst_gain"], fields["candidate_on_block"] = worst, on_block
    damper = {**fixed, "omega_ratio": 1.0 / best[0], "zeta": best[1]}
    unknown = sum(int(np.sum(t["undetermined"])) for t in tiles.values())
    warn_undetermined("design", unknown)
    warn_t_max("design", sum(int(np.sum(t["t_max"])) for t in tiles.values()), setting.t_after)
    edges = int(at_edge(best[0], r_grid)), int(at_edge(best[1], z_grid))
    config = {
        "kind": "design",
        **setting.record(),
        "damper": fixed,
        "Tm_ratio": Tm.record(),
        "zeta_grid": zeta.record(),
        "refine": refine,
        **grids,
        "directions": chosen,
    }
    data = design_data(config, Om, signs, r_grid, z_grid, fields)
    summary = design_summary(setting, data, damper, L, *edges)
    warn_design(summary)
    return Study(
        "design",
        config,
        data,
        summary={
            **summary,
            "candidates": len(points),
            "candidates_on_block": int(on_block.sum()),
            "undetermined": unknown,
            "directions": chosen,
        },
        run={
            "tiles_computed": sum(s.computed for s in stats),
            "tiles_reused": sum(s.reused for s in stats),
            "wall_s": round(sum(s.wall for s in stats), 3),
            "run_folders": {k: v.name for k, v in folders.items()},
        },
        tabulate=design_tables,
    )


def design_data(config: dict, Omega, signs, r_coarse, zeta_coarse, fields: dict):
    """A design's results as labelled data (:data:`DIMS`), with the coordinates in non-dimensional and SI terms
    and units."""
    import xarray as xr

    coords = {
        "part": ("part", np.array(PARTS), {"long_name": "; ".join(f"{p}: {PART_NAMES[p]}" for p in PARTS)}),
        "Omega": ("Omega", Omega, coordinate_attrs("Omega", config)),
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
        "r_coarse": ("r_coarse", r_coarse, coordinate_attrs("r_coarse", config)),
        "zeta_coarse": ("zeta_coarse", zeta_coarse, coordinate_attrs("zeta_coarse", config)),
    }
    coords.update(si_coordinates(config, coords))
    return xr.Dataset({k: (DIMS[k], v, _attrs(k, config)) for k, v in fields.items()}, coords=coords)


def _attrs(name: str, config: dict) -> dict:
    """Units and meaning of the variable ``name`` of a design's data: those of its field (``candidate_r``:
    ``r``), said of the design (:data:`NOTES`) or of every damper evaluated."""
    field = "gain_flag" if name == "flag_opt" else name.removeprefix("candidate_").removesuffix("_opt")
    attrs = field_attrs(field, config)
    attrs["long_name"] += NOTES.get(name, ", of each damper evaluated" if name.startswith("candidate_") else "")
    return attrs


def envelope(data):
    """A design's ``beta_min`` reduced over ``sign`` (:func:`rocking.study.directions.beta_min_envelope`): the
    smaller ``beta_min`` of the directions of each part and Omega, with its ``beta_safe``, ``flag`` and
    ``impacts``, and the responses without a verdict summed. ``data``: a design :class:`~rocking.study.result.Study`
    or its data."""
    import xarray as xr

    data = study_data(data, ("design",))
    reduced = beta_min_envelope({k: data[k].transpose(..., "sign").values for k in COLUMN_FIELDS})
    reduced.pop("worst_sign_index")
    return xr.Dataset(
        {k: (("part", "Omega"), v, data[k].attrs) for k, v in reduced.items()}, coords=data.drop_dims("sign").coords
    )


def stroke_use(data):
    """The design's largest stroke over its half-stroke ``L`` at each ``Omega`` of the band, over the directions."""
    return np.nanmax(data["stroke_use"].transpose(..., "sign").values, axis=-1)


def design_summary(setting: Setting, data, damper: dict, L: float, r_edge: int, zeta_edge: int) -> dict:
    """The damper in SI and non-dimensional terms, its worst gain over the band and where, and the flags."""
    block = setting.block
    m = damper["gamma"] * block.M
    omega_m = damper["omega_ratio"] * block.p
    _, k_b, c_b = (float(v) for v in edge_stops(block, m, block.B / 2 - L))
    gain, Omega = data["gain_opt"].values, data["Omega"].values
    defined = np.isfinite(gain)
    i = int(np.nanargmin(gain)) if defined.any() else None
    summary = {
        "damper": {
            "m_kg": m,
            "k_m_N_per_m": m * omega_m**2,
            "c_N_s_per_m": 2 * damper["zeta"] * m * omega_m,
            "T_m_s": 2 * np.pi / omega_m,
            "h_m": damper["h"],
            "L_m": L,
            "k_b_N_per_m": k_b,
            "c_b_N_s_per_m": c_b,
            "gamma": damper["gamma"],
            "Tm_ratio": 1.0 / damper["omega_ratio"],
            "zeta": damper["zeta"],
        },
        "worst_gain": None if i is None else float(gain[i]),
        "worst_at_Omega": None if i is None else float(Omega[i]),
        "worst_gain_is_lower_bound": None if i is None else bool(data["flag_opt"].values[i] == ABOVE),
        "gain_undefined_at": [float(x) for x in Omega[~defined]],
        "Tm_at_edge": r_edge,
        "zeta_at_edge": zeta_edge,
        "stroke_use_max": float(np.nanmax(stroke_use(data), initial=0.0)),
        "stop_contacts_max": int(data["stop_contacts"].values.max()),
    }
    return {**summary, "verdict": verdict(summary)}


def verdict(summary: dict) -> dict:
    """What a design achieved (its ``summary``'s worst gain and where): ``{"code": ..., "text": ...}``, the code a
    key of :data:`VERDICTS` and the text its sentence: it helps (worst gain > ``USELESS_GAIN``), gains nothing
    useful, makes some pulse worse (worst gain < 1), or has no verdict (the gain is undefined over the band)."""
    worst = summary["worst_gain"]
    if worst is None:
        code = "undefined"
        text = (
            ": the gain is undefined over the whole band (the block alone survives the beta scan; widen beta= / --beta)"
        )
        return {"code": code, "text": VERDICTS[code] + text}
    where = f"at Omega = {summary['worst_at_Omega']:.3g}"
    bound = ", a lower bound: the damped block survived the scan there" if summary["worst_gain_is_lower_bound"] else ""
    if worst > USELESS_GAIN:
        code, text = "helps", f": worst gain {worst:.2f} over the band ({where}{bound})"
    elif worst >= 1.0:
        code, text = "no_useful_gain", f" (worst gain {worst:.2f} <= {USELESS_GAIN:g}, {where}{bound})"
    else:
        code = "harms"
        text = f": worst gain {worst:.2f} < 1 ({where}{bound}); no damper of this budget and stroke helps"
        text += " over the whole band"
    return {"code": code, "text": VERDICTS[code] + text}


def edge_warnings(summary: dict) -> list[str]:
    """One sentence per optimal parameter of a design (its ``summary``) at an end of its search range, naming the
    keyword (and option) that widens it."""
    damper, out = summary["damper"], []
    for name, value, edge, option in (
        ("T_m p / 2 pi", damper["Tm_ratio"], summary["Tm_at_edge"], "Tm_ratio= / --Tm-ratio"),
        ("zeta", damper["zeta"], summary["zeta_at_edge"], "zeta_grid= / --zeta-grid"),
    ):
        if edge:
            end, bound = ("smallest", "MIN below") if edge < 0 else ("largest", "MAX above")
            out.append(
                f"design: the optimal {name} = {value:.3g} is the {end} of its search range: the best may lie "
                f"beyond; widen it ({option} MIN MAX N, {bound} {value:.3g})"
            )
    return out


def warn_design(summary: dict) -> None:
    """Warn, attributed to the user's call, a :class:`DesignWarning` with the verdict of a design that does not
    help, and an :class:`~rocking.study.optimize.EdgeWarning` per optimum at an end of its search range."""
    found = summary["verdict"]
    if found["code"] != "helps":
        warnings.warn(f"design: {found['text']}", DesignWarning, stacklevel=_user_stacklevel())
    for text in edge_warnings(summary):
        warnings.warn(text, EdgeWarning, stacklevel=_user_stacklevel())


def designed_damper(result) -> Damper:
    """The damper a design chose, built: a :class:`~rocking.Damper` with its :class:`~rocking.Stops`, in SI units,
    that :func:`rocking.simulate` and every study (``damper=``) take as it is.

    Parameters
    ----------
    result : Study or xarray.Dataset
        What :func:`rocking.design` returned (``study=True`` or not), or a design read by :func:`rocking.load`.

    Returns
    -------
    Damper
        Mass ``m``, spring ``k_m``, dashpot ``c``, guide height ``h`` and stops at ``L`` with pads ``k_b``, ``c_b``
        (the summary's ``damper``).
    """
    if isinstance(result, Study):
        if result.kind != "design":
            raise ParameterError(f"designed_damper takes a design's result (got a {result.kind} study)")
        summary = result.summary
    else:  # a Dataset: the summary is its JSON attribute
        attrs = getattr(result, "attrs", {})
        if attrs.get("kind") != "design" or "summary" not in attrs:
            raise ParameterError(f"designed_damper takes a design's result (got {type(result).__name__})")
        summary = json.loads(attrs["summary"])
    d = summary["damper"]
    stops = Stops(L=d["L_m"], k_b=d["k_b_N_per_m"], c_b=d["c_b_N_s_per_m"])
    return Damper(m=d["m_kg"], k_m=d["k_m_N_per_m"], c=d["c_N_s_per_m"], h=d["h_m"], stops=stops)


def design_tables(data, config: dict) -> dict:
    """The tables of a design: the answer over the band (:func:`design_table`), its candidates
    (:func:`candidates_table`)."""
    return {"design": design_table(data), "design-candidates": candidates_table(data)}


def design_table(data) -> dict:
    """One CSV row per ``Omega`` of the band: the envelopes, the gain of the design, its stroke use."""
    # A beta_min not reached in the scan is a censored value (spectrum.censored): NaN and its lower bound.
    bare = envelope(data).sel(part="bare")
    enveloped = censored({"beta_min": bare["beta_min"].values, "flag": bare["flag"].values})
    table = {
        "Omega": data["Omega"].values,
        "T_g": data["T_g"].values,
        "bare_beta_min": enveloped["beta_min"],
        "bare_beta_min_lower_bound": enveloped["beta_min_lower_bound"],
        "bare_beta_min_is": flag_words(bare["flag"].values),
    }
    beta = data["beta_min"].transpose("part", "Omega", "sign")
    flag = data["flag"].transpose("part", "Omega", "sign")
    for i, sign in enumerate(data["sign"].values):
        for part in ("bare", "damper"):
            one = censored({"beta_min": beta.sel(part=part).values[:, i], "flag": flag.sel(part=part).values[:, i]})
            table[f"{part}_beta_min_{SIGN_NAMES[sign]}"] = one["beta_min"]
            table[f"{part}_beta_min_lower_bound_{SIGN_NAMES[sign]}"] = one["beta_min_lower_bound"]
    table.update(gain=data["gain_opt"].values, gain_lower_bound=data["flag_opt"].values == ABOVE)
    table.update(
        stroke_use=stroke_use(data),
        stop_contacts=data["stop_contacts"].max("sign").values,
        bumper_force_max_N=np.nanmax(data["bumper_force_max"].transpose(..., "sign").values, axis=-1),
    )
    return table


def candidates_table(data) -> dict:
    """One CSV row per damper evaluated: ``T_m p / (2 pi)``, ``zeta`` and the worst gain over the band."""
    return {
        "Tm_p_over_2pi": data["candidate_r"].values,
        "zeta": data["candidate_zeta"].values,
        "worst_gain": data["candidate_worst_gain"].values,
        "mass_stays_on_block": data["candidate_on_block"].values,
    }
