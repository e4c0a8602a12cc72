"""The overturning map: the outcome of every pulse of an ``(Omega, beta)`` grid, with and without a damper.

Each cell of the grid of pulse frequency ratios ``Omega = omega_g / p`` and
amplitude ratios ``beta = a_g / (g tan(alpha))`` (``docs/model.md`` section 9) is
one response of the block alone (part ``bare``) and one of the block with its
damper (part ``damper``: the paper's ``omd`` given as a :class:`Tuning`, or any
generated model as a :class:`Variant`). A cell's *outcome* is ``SAFE`` (-1) or the number of
impacts before overturning (0: overturned without impact). The comparison map
(*effect*) marks the cells the damper saves (+1: the bare block overturns, the
damped one does not) and those it loses (-1: the reverse).

By default the map is *adaptive* (:mod:`rocking.study.adaptive`): each part computes a coarse lattice of
cells (every ``coarse``-th, 16 by default) and refines, down to single cells, only where neighbouring cells
differ in outcome class; the other cells take the class of the computed cells around them. Outcomes and the
effect are complete; ``computed`` says which cells of each part were computed, and the continuous fields of the
others are not invented: ``theta_max``, ``x_max``, ``bumper_force_max`` are NaN there, and ``impacts`` of a
safe cell, ``stop_contacts`` and ``status`` are :data:`NOT_COMPUTED` where they do not follow from the class.
An adaptive map can miss a feature of another class smaller than the coarse step along both axes, one that
falls entirely between the computed cells of a block whose computed cells agree (:mod:`rocking.study.adaptive`);
its summary counts how many cells of each class were inferred, not computed, and how many more saved and lost
cells they could hold (:func:`inferred_counts`); ``full=True`` computes every cell.

The cells are cut into tiles; each tile is one call of :func:`rocking.sim.cases.run_cases` (a rectangle of
the grid, :func:`map_tile`, for a full map; a list of cells, :func:`cells_tile`, for each round of an
adaptive one), run by :func:`rocking.study.tiles.run_tiles`.
"""

from __future__ import annotations

import hashlib
import time
import warnings
from functools import partial
from os import PathLike
from pathlib import Path

import numpy as np

from ..model.params import BUMPER_DEPTH, Block, ParameterError
from ..sim.boundary import UNDETERMINED
from ..sim.cases import pulse_cases, run_cases
from ..sim.problem import STATUS
from . import directions
from .adaptive import COARSE, Refinement, check_coarse, check_verify, guarantee
from .config import (
    Grid,
    Setting,
    Tuning,
    Variant,
    check_cells,
    check_type,
    floor_attrs,
    is_count,
    part_config,
    vertical_attrs,
)
from .dataset import coordinate_attrs, field_attrs, si_coordinates
from .directions import SIGN_NAMES, choose
from .result import Study
from .tiles import LOCAL, Execution, Interrupted, Task, TileStats, interleave, run_folder, run_tiles
from .vocabulary import (
    NOT_COMPUTED,
    OVERTURNS,
    PART_NAMES,
    REGIMES,
    SAFE,
    SLIDES,
    SLIDES_AND_ROCKS,
    combined_regime,
    regime,
    resolution_of,
)

#: Result fields kept per response.
FIELDS = ("overturned", "impacts", "theta_max", "x_max", "status", "stop_contacts", "bumper_force_max")

#: Result fields kept per response beside :data:`FIELDS` on a floor with friction (docs/model.md section 15): the
#: peak slip and the residual displacement of the base, m, and its slip episodes. A map on the paper's floor has
#: none of them (its data are those it had before friction), nor its ``regime``.
SLIP_FIELDS = ("u_max", "u_end", "slides")

#: Result fields kept per response beside :data:`FIELDS` where the pulses have a vertical component (docs/model.md
#: section 16): the takeoffs, the time off the floor, s, and the highest base point's peak height, m; with
#: ``flew`` (:func:`with_flew`), which an adaptive map's class gives where a cell was not computed.
FLIGHT_FIELDS = ("flights", "flight_time", "jump_max")

#: The regimes in which the base slid without overturning.
SLID = (SLIDES, SLIDES_AND_ROCKS)

#: The parts of a map: the block alone, and with its damper (the coordinate ``part`` of its data).
PARTS = ("bare", "damper")

#: The dimensions of every variable of a map's data (:func:`map_data`), coordinates included.
DIMS = {
    "part": ("part",),
    "Omega": ("Omega",),
    "beta": ("beta",),
    "sign": ("sign",),
    "T_g": ("Omega",),
    "a_g": ("beta",),
    **dict.fromkeys((*FIELDS, *SLIP_FIELDS, "regime", *FLIGHT_FIELDS, "flew"), ("part", "Omega", "beta", "sign")),
    "computed": ("part", "Omega", "beta"),
}

#: The integer fields of :data:`FIELDS` (and ``overturned``), with their types: :data:`NOT_COMPUTED` where a
#: cell of an adaptive map was not computed and its class does not give them.
INTEGERS = {
    "overturned": bool,
    "impacts": int,
    "status": int,
    "stop_contacts": int,
    "slides": int,
    "regime": int,
    "flights": int,
    "flew": int,
}

#: The refinement class of a response that did not overturn on a floor with friction is this minus its regime
#: (:data:`rocking.study.vocabulary.REGIMES`): below every ``-2 - status`` of :func:`response_classes`.
REGIME_CLASS = -100

#: The refinement classes of a response that flew (``flights > 0``, docs/model.md section 16) and landed to a
#: verdict without overturning, and of one that flew and overturned (its impacts not told): classes of their own,
#: below every ``-2 - status`` of :func:`response_classes` and above every regime's.
FLIES_AND_LANDS_CLASS, FLIES_AND_OVERTURNS_CLASS = -50, -51

#: Keys of a damper's keyword arguments that are fixed for a whole study (not per case arrays).
FIXED = ("model", "params", "stops", "stroke")

#: Default tile: Omega values x beta values per call of run_cases. About 0.1 s of
#: C on the reference block: the Python around a tile (its cases, storing it),
#: which holds the GIL, is then some 2 % of it, and local worker threads scale.
TILE = (32, 32)


def respond(setting: Setting, Omega, beta, damper: dict | None = None, sign=1) -> dict:
    """Responses to the pulses ``(Omega, beta, sign)``, shaped like their broadcast.

    Parameters
    ----------
    setting : Setting
        Block and solver.
    Omega, beta : array_like
        Pulse frequency and amplitude ratios; broadcast together.
    damper : dict, optional
        Keyword arguments of :func:`rocking.sim.cases.pulse_cases`: ``gamma``,
        ``omega_ratio``, ``zeta``, ``h`` (array_like, broadcasting with the
        pulses) or ``model`` and ``params`` (:meth:`Variant.case_args`);
        ``None`` for the bare block.
    sign : int or array_like
        Direction of each pulse, +1 or -1 (broadcast with the pulses).

    Returns
    -------
    dict of ndarray
        The arrays :func:`response_fields`.
    """
    arrays = {k: v for k, v in (damper or {}).items() if k not in FIXED}
    shapes = (np.shape(Omega), np.shape(beta), np.shape(sign), *(np.shape(v) for v in arrays.values()))
    cases = pulse_cases(
        setting.block,
        Omega,
        beta,
        rtol=setting.rtol,
        t_after=setting.t_after,
        sign=sign,
        **setting.pulse_args(),
        **(damper or {"gamma": 0.0}),
    )
    result = run_cases(cases, backend=setting.backend, threads=1)
    return {k: result[k].reshape(np.broadcast_shapes(*shapes)) for k in response_fields(setting)}


def response_fields(setting: Setting) -> tuple[str, ...]:
    """The result fields :func:`respond` keeps: :data:`FIELDS`, :data:`SLIP_FIELDS` on a floor with friction and
    :data:`FLIGHT_FIELDS` with a vertical component."""
    slip = SLIP_FIELDS if setting.floor.slides else ()
    return (*FIELDS, *slip, *(FLIGHT_FIELDS if setting.vertical is not None else ()))


def preflight(setting: Setting, damper: dict | None = None) -> None:
    """Run one trivial case of the bare block and of ``damper`` here, before any worker starts.

    ``damper``: keyword arguments of :func:`rocking.sim.cases.pulse_cases`
    (default: a small ``omd`` damper). Its parameters are checked too.

    A missing or unbuildable back end then fails at once, with a clear
    message, and the models and C libraries are built (and cached) and loaded
    once, here, not by every worker: threads share what this loads.

    Raises
    ------
    ParameterError
        If the back end cannot run.
    """
    from ..sim.cbuild import CBuildError

    try:
        for case in (None, damper or {"gamma": 0.01}):
            respond(setting, 1.0, 0.0, case)
    except (ImportError, CBuildError) as exc:
        raise ParameterError(f"backend {setting.backend!r} is not available ({exc}); try --backend numpy") from None


def outcome(overturned, impacts) -> np.ndarray:
    """:data:`SAFE`, or the impacts before overturning."""
    return np.where(overturned, impacts, SAFE)


#: The statuses without a verdict: a bound on the run's work, the floor's normal force reaching 0 on a model without
#: flight functions (``flight``: the base may leave the ground, out of that model's scope, docs/model.md section 14),
#: or a landing with no consistent impulse (``jammed``, section 16). A flight model's response that flew and landed
#: has the verdict it came to: a class of its own (:data:`FLIES_AND_LANDS_CLASS`).
NO_VERDICT = (*UNDETERMINED, "flight", "jammed")


def undetermined(status) -> np.ndarray:
    """Where a run ended without a verdict (:data:`NO_VERDICT`): cut short by a bound on its work (``max_events``,
    ``max_steps``), where the base would leave the ground on a model without flight functions (``flight``), or
    jammed at a landing (``jammed``)."""
    return np.isin(status, [STATUS.index(name) for name in NO_VERDICT])


def response_classes(overturned, impacts, status, regimes=None, flights=None) -> np.ndarray:
    """The class of each response that an adaptive map refines on: its :func:`outcome`, or ``-2 - status`` for a
    response without a verdict (:func:`undetermined`), which no cell around it can tell. ``regimes`` (on a floor
    with friction, :func:`rocking.study.vocabulary.regime`) part the responses that did not overturn by what
    they did: :data:`REGIME_CLASS` minus their regime. ``flights`` (with a vertical component) part those that
    flew: :data:`FLIES_AND_LANDS_CLASS` and :data:`FLIES_AND_OVERTURNS_CLASS`."""
    classes = outcome(overturned, impacts)
    if regimes is not None:
        classes = np.where(np.asarray(overturned), classes, REGIME_CLASS - np.asarray(regimes))
    if flights is not None:
        flew = np.where(np.asarray(overturned), FLIES_AND_OVERTURNS_CLASS, FLIES_AND_LANDS_CLASS)
        classes = np.where(np.asarray(flights) > 0, flew, classes)
    return np.where(undetermined(status), -2 - np.asarray(status), classes)


def with_flew(arrays: dict) -> dict:
    """The arrays of responses with a vertical component (their :data:`FLIGHT_FIELDS`) with ``flew``: 1 where the
    base left the ground (``flights > 0``), else 0; ``arrays`` itself without."""
    if "flights" not in arrays:
        return arrays
    return {**arrays, "flew": (np.asarray(arrays["flights"]) > 0).astype(np.int64)}


def with_regime(arrays: dict, setting: Setting) -> dict:
    """The arrays of responses on a floor with friction (their :data:`SLIP_FIELDS`) with their ``regime``
    (:func:`rocking.study.vocabulary.regime`, at ``setting``'s resolution); ``arrays`` itself on the paper's
    floor."""
    if "u_max" not in arrays:
        return arrays
    resolution = resolution_of(setting.rtol, setting.block.alpha)
    return {**arrays, "regime": regime(arrays["overturned"], arrays["theta_max"], arrays["u_max"], resolution)}


def effect(bare_overturned, damper_overturned, unknown=False) -> np.ndarray:
    """+1 where the damper saves the block, -1 where it makes it overturn, 0 elsewhere and where ``unknown``."""
    change = np.asarray(bare_overturned, int) - np.asarray(damper_overturned, int)
    return np.where(unknown, 0, change)


def warn_undetermined(study: str, count: int) -> None:
    """Warn that ``count`` responses of ``study`` ended without a verdict (:data:`UNDETERMINED`)."""
    if count:
        warnings.warn(
            f"{study}: {count} response(s) ended at a bound on their work (status {' or '.join(UNDETERMINED)}) "
            "or, with a vertical component, where the base would leave the ground on a model without flight "
            "functions (status flight, docs/model.md section 14) or at a landing with no consistent impulse (status "
            "jammed, section 16) before overturning or coming to rest; they count as not overturned (a map "
            "leaves the damper's effect there at 0). A damper far stiffer than the block (omega_ratio >> 10) with "
            "little damping needs many steps: docs/simulation.md, rule 5",
            UndeterminedWarning,
            stacklevel=3,
        )


class UndeterminedWarning(UserWarning):
    """Some responses of a study ended without a verdict (a status of :data:`NO_VERDICT`)."""


def reached_t_max(status) -> np.ndarray:
    """Where a run reached ``t_max`` (``t_after`` past the pulse) before overturning, rest or a final bound: it
    counts as not overturned, but may overturn later."""
    return np.asarray(status) == STATUS.index("t_max")


def warn_t_max(study: str, count: int, t_after: float) -> None:
    """Warn that ``count`` responses of ``study`` reached ``t_max`` (:func:`reached_t_max`): a short ``t_after``
    turns runs that would overturn later into safe ones, silently but for this."""
    if count:
        warnings.warn(
            f"{study}: {count} response(s) reached t_max (t_after = {t_after:g} s after the pulse) before "
            "overturning, rest or a final bound; they count as not overturned, and some may overturn later: "
            "follow them longer (t_after / --t-after)",
            TMaxWarning,
            stacklevel=3,
        )


class TMaxWarning(UserWarning):
    """Some responses of a study reached ``t_max`` before a verdict: they count as not overturned."""


def map_tile(payload: tuple) -> dict:
    """One tile: ``(setting, damper_or_None, Omega_values, beta_values, signs)`` -> arrays ``(nOmega, nbeta,
    nsigns)``."""
    setting, damper, Omega, beta, signs = payload
    return respond(setting, Omega[:, None, None], beta[None, :, None], damper, np.asarray(signs)[None, None, :])


def cells_tile(payload: tuple) -> dict:
    """Cells of an adaptive map: ``(setting, damper_or_None, Omega_values, beta_values, signs)``, a cell per
    pair ``(Omega[c], beta[c])`` -> arrays ``(ncells, nsigns)``."""
    setting, damper, Omega, beta, signs = payload
    return respond(setting, Omega[:, None], beta[:, None], damper, np.asarray(signs)[None, :])


def check_damper(damper) -> None:
    """Refuse anything but a :class:`Tuning` or a :class:`Variant` as a study's damper."""
    if not isinstance(damper, (Tuning, Variant)):
        raise ParameterError(
            "the damper must be a rocking.study.config.Tuning (omd) or Variant (any model) "
            f"(got {type(damper).__name__})"
        )


def check_study(setting, execution, runs, **grids) -> None:
    """Refuse inputs of a study of the wrong type, and grids of pulses too large (:func:`check_cells`).

    ``grids``: the study's grids by parameter name (``Omega=..., beta=...``).
    """
    check_type("setting", setting, Setting, "a rocking.Setting")
    for name, grid in grids.items():
        check_type(name, grid, Grid, f'a rocking.Grid (e.g. Grid("{name}", 1.0, 10.0, 50))')
    check_type("execution", execution, Execution, "a rocking.Execution")
    check_type("runs", runs, (str, PathLike), "a folder (str or Path)")
    check_cells(*grids.values())


def _check_tile(tile) -> tuple[int, int]:
    try:
        a, b = tile
    except (TypeError, ValueError):
        a = b = None
    if not (is_count(a) and is_count(b)):
        raise ParameterError(f"tile must be two integers (Omega values, beta values) (got {tile!r})")
    if a < 1 or b < 1:
        raise ParameterError(f"tile sizes must be >= 1 (got {tile!r})")
    return int(a), int(b)


def overturning_map(
    setting: Setting,
    tuning: Tuning | Variant,
    Omega: Grid,
    beta: Grid,
    execution: Execution = LOCAL,
    *,
    runs: str | Path = "out/runs",
    tile: tuple[int, int] = TILE,
    directions: str = "auto",
    full: bool = False,
    coarse: int = COARSE,
    verify: int | None = None,
    on_tile=None,
) -> Study:
    """Outcome over the ``Omega x beta`` grid for the bare block and with the damper ``tuning``, in both
    directions of the pulse (:mod:`rocking.study.directions`) and their envelope.

    Parameters
    ----------
    setting : Setting
        Block and solver.
    tuning : Tuning or Variant
        The damper: the paper's ``omd`` relative to the block, or any
        generated model with its parameters.
    Omega, beta : Grid
        Pulse frequency and amplitude ratios.
    execution : Execution
        Where the tiles run.
    runs : path
        Folder of the run folders (finished tiles, for resuming).
    tile : (int, int)
        Omega values x beta values per tile.
    directions : {"auto", "both", "positive", "negative"}
        Signs of the pulses (:func:`rocking.study.directions.choose`): ``"auto"`` runs both unless the block
        and its damper are symmetric.
    full : bool, optional
        Compute every cell. Default False: the map is adaptive (:mod:`rocking.study.adaptive`), refined on
        each part's outcome classes from a lattice of every ``coarse``-th cell; it can miss a feature of
        another class smaller than ``coarse`` cells along both axes.
    coarse : int, optional
        The coarse step of an adaptive map, cells: a power of two in [1,
        :data:`rocking.study.adaptive.MAX_COARSE`] (1 computes every cell). Default 16.
    verify : int, optional
        The first step of the verification of an adaptive map (:class:`rocking.study.adaptive.Refinement`): 0
        (none) or a power of two in [1, ``coarse``]; every region of a class that holds a square of ``verify x
        verify`` cells, or extends over ``coarse`` cells along an axis, is found. Default ``coarse``.
    on_tile : callable, optional
        Passed to :func:`rocking.study.tiles.run_tiles` (each round of an adaptive map is a call).

    Returns
    -------
    Study
        Its data (:func:`map_data`): the :data:`FIELDS` of every response, dimensions ``(part, Omega, beta,
        sign)`` (``part``: ``bare`` and ``damper``), and ``computed`` (``(part, Omega, beta)``, bool: the cells
        computed; where not, the fields that do not follow from the outcome class are NaN or
        :data:`NOT_COMPUTED`). Their envelope over the directions, the direction that governs each cell and
        the damper's ``effect`` are a reduction over ``sign`` (:func:`envelope`).
        ``config["refinement"]`` records ``adaptive``, ``coarse``, ``verify`` and ``edges`` (the verification
        computed the edges of the coarse blocks), ``summary["guarantee"]`` what an adaptive map can miss
        (:func:`rocking.study.adaptive.guarantee`) and the counts of :func:`inferred_counts` what rests on
        cells not computed; ``run["responses"]`` counts the
        responses computed, ``run["responses_full_grid"]`` those of every cell, ``run["rounds"]`` the rounds of tiles.

    Raises
    ------
    ParameterError
        Naming the parameter and its valid range, before any work: inputs of
        the wrong type, a ``coarse`` that is not a power of two in range, more than
        :data:`rocking.study.config.MAX_CELLS` cells, a folder that cannot be written, a back end or a Dask cluster
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

    Examples
    --------
    >>> import tempfile, rocking
    >>> setting = rocking.Setting(rocking.Block.reference())
    >>> from rocking.study.overturning_map import overturning_map
    >>> study = overturning_map(
    ...     setting, rocking.Tuning(0.05), rocking.Grid("Omega", 2.0, 6.0, 3), rocking.Grid("beta", 1.0, 9.0, 3),
    ...     rocking.Execution(workers=1, progress=False), runs=tempfile.mkdtemp())
    >>> study.data["overturned"].dims
    ('part', 'Omega', 'beta', 'sign')
    >>> from rocking.study.overturning_map import envelope
    >>> both = envelope(study.data)  # the worse of the two directions of each pulse
    >>> both["overturned"].sel(part="bare").values.astype(int)  # rows: Omega, columns: beta
    array([[0, 1, 1],
           [0, 1, 1],
           [0, 1, 1]])
    >>> study.config["directions"]["signs"]  # the reference block is eccentric (e > 0): both directions
    [1, -1]
    >>> both["effect"].values  # +1: the damper saves the block (in both directions), -1: it loses it
    array([[0, 0, 0],
           [0, 0, 0],
           [0, 0, 0]])
    >>> positive = study.data["overturned"].sel(sign=1)
    >>> (positive.sel(part="bare") & ~positive.sel(part="damper")).values.astype(int)
    array([[0, 0, 0],
           [0, 1, 0],
           [0, 0, 1]])

    The cells the damper saves from the positive pulses alone overturn under the mirrored ones.
    """
    check_study(setting, execution, runs, Omega=Omega, beta=beta)
    tile = _check_tile(tile)
    check_type("full", full, bool, "True or False")
    coarse = check_coarse(coarse)
    verify = check_verify(coarse if verify is None else verify, coarse)
    check_damper(tuning)
    chosen = choose(directions, setting.block, tuning)
    signs = chosen["signs"]
    Om, b = Omega.values(), beta.values()
    grids = {"Omega": Omega.record(), "beta": beta.record(), "tile": list(tile), "signs": signs}
    # A full map's tiles keep the configuration (and folders) they had before maps were adaptive.
    refinement = (
        {"adaptive": False} if full else {"adaptive": True, "coarse": coarse, "verify": verify, "edges": verify > 0}
    )
    tiles_of = {} if full else {"refinement": refinement}
    record = tuning.record()
    parts, folders = dict(zip(PARTS, (None, tuning.case_args()))), {}
    shape = (len(PARTS), Om.size, b.size, len(signs))
    kept = (*response_fields(setting), *(("regime",) if setting.floor.slides else ()))
    kept += ("flew",) if setting.vertical is not None else ()
    fields: dict[str, np.ndarray] = {
        k: np.full(shape, False if k == "overturned" else NOT_COMPUTED, INTEGERS[k]) for k in kept if k in INTEGERS
    }
    fields.update({k: np.full(shape, np.nan) for k in kept if k not in INTEGERS})
    for part, described in zip(PARTS, (None, record)):
        config = part_config("map", part, setting, damper=described, **grids, **tiles_of)
        folders[part] = run_folder(runs, config)

    preflight(setting, tuning.case_args())
    run_map = _full if full else partial(_adaptive, refinement=refinement)
    stats, rounds, computed = run_map(setting, parts, folders, (Om, b, signs), fields, execution, tile, on_tile)
    config = {
        "kind": "map",
        **setting.record(),
        "damper": record,
        **grids,
        "directions": chosen,
        "refinement": refinement,
    }
    data = map_data(config, Om, b, signs, fields, computed)
    warn_undetermined("map", int(undetermined(fields["status"]).sum()))
    warn_t_max("map", int(reached_t_max(fields["status"]).sum()), setting.t_after)
    return Study(
        "map",
        config,
        data,
        summary={
            **map_summary(data, setting.block.B / 2),
            "directions": chosen,
            "refinement": refinement,
            "guarantee": guarantee(refinement, (spacing(Om), spacing(b)), every_cell=bool(computed.all())),
        },
        run={
            **stats.record(),
            "run_folders": {part: folder.name for part, folder in folders.items()},
            "responses": len(signs) * int(computed.sum()),
            "responses_full_grid": len(parts) * len(signs) * Om.size * b.size,
            "rounds": rounds,
        },
        tabulate=map_tables,
    )


def map_data(config: dict, Omega, beta, signs, fields: dict, computed):
    """A map's results as labelled data: the :data:`FIELDS` of every response, ``(part, Omega, beta, sign)``, and
    ``computed`` (``(part, Omega, beta)``), with the coordinates in non-dimensional and SI terms and units."""
    import xarray as xr

    coords = {
        "part": (
            "part",
            np.array(PARTS),
            {"long_name": "part of the study: " + ", ".join(PART_NAMES[p] for p in PARTS)},
        ),
        **{dim: (dim, values, coordinate_attrs(dim, config)) for dim, values in (("Omega", Omega), ("beta", beta))},
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
    }
    coords.update(si_coordinates(config, coords))
    variables = {k: (DIMS[k], v, field_attrs(k, config)) for k, v in fields.items()}
    variables["computed"] = (DIMS["computed"], computed, field_attrs("computed", config))
    return xr.Dataset(variables, coords=coords, attrs={**vertical_attrs(config), **floor_attrs(config)})


def envelope(data):
    """A map's responses reduced over ``sign``: the envelope of both directions of each pulse
    (:func:`rocking.study.directions.envelope`), and the damper's ``effect`` on it (``(Omega, beta)``).

    ``worst_sign`` is 0 where the direction that governs is not known: a safe cell not computed (which direction
    governs a safe cell is told by ``theta_max``). ``data``: a map :class:`~rocking.study.result.Study` or its data.
    """
    data = directions.study_data(data, ("map",))
    status = data["status"]
    flight = [k for k in (*FLIGHT_FIELDS, "flew") if k in data]  # with a vertical component
    out = directions.envelope(data[[*FIELDS, *flight]], status.copy(data=undetermined(status.values)))
    computed = data["computed"].transpose(*out["overturned"].dims).values
    not_known = ~computed & ~out["overturned"].values & ~undetermined(out["status"].values)
    out["worst_sign"] = out["worst_sign"].copy(data=np.where(not_known, 0, out["worst_sign"].values))
    bare, damper = (out.sel(part=part) for part in PARTS)
    unknown = undetermined(bare["status"].values) | undetermined(damper["status"].values)
    change = effect(bare["overturned"].values, damper["overturned"].values, unknown)
    out["effect"] = (("Omega", "beta"), change, field_attrs("effect", {}))
    if "regime" in data:  # a floor with friction: what the pulse did in either direction, the larger slip
        by_sign = data[["regime", "u_max"]].transpose(..., "sign")
        out["regime"] = (by_sign["regime"].dims[:-1], combined_regime(by_sign["regime"].values), data["regime"].attrs)
        out["u_max"] = (by_sign["u_max"].dims[:-1], directions.largest(by_sign["u_max"].values), data["u_max"].attrs)
    return out


def spacing(values: np.ndarray) -> float:
    """The widest step between neighbouring values of a grid (0 for one value)."""
    return float(np.diff(values).max()) if values.size > 1 else 0.0


def _full(setting, parts: dict, folders: dict, grid: tuple, fields: dict, execution, tile, on_tile):
    """Every cell of the map, a rectangle of ``tile`` cells per tile, into ``fields``; ``(TileStats, 1, computed)``."""
    Om, b, signs = grid
    groups, where = [], {}
    for index, (part, damper) in enumerate(parts.items()):
        part_tasks: list[Task] = []
        groups.append(part_tasks)
        for i in range(0, Om.size, tile[0]):
            for j in range(0, b.size, tile[1]):
                rows, cols = slice(i, i + tile[0]), slice(j, j + tile[1])
                payload = (setting, damper, Om[rows], b[cols], signs)
                expect = dict.fromkeys(response_fields(setting), (Om[rows].size, b[cols].size, len(signs)))
                task = Task(folders[part] / f"tile-{i}-{j}.npz", map_tile, payload, expect)
                part_tasks.append(task)
                where[task.path] = (index, rows, cols)

    def place(task: Task, tile_arrays: dict) -> None:
        index, rows, cols = where[task.path]
        arrays = with_flew(with_regime(tile_arrays, setting))
        for k in fields:
            fields[k][index, rows, cols] = arrays[k]

    stats = run_tiles(interleave(*groups), place, execution, backend=setting.backend, desc="map", on_tile=on_tile)
    return stats, 1, np.ones((len(parts), Om.size, b.size), bool)


def _adaptive(setting, parts: dict, folders: dict, grid: tuple, fields: dict, execution, tile, on_tile, refinement):
    """The map refined on each part's outcome classes (:mod:`rocking.study.adaptive`), into ``fields``;
    ``(TileStats, rounds, computed)``.

    Each round computes the corners its part's refinement asks for, in tiles of as many cells as ``tile`` holds
    (the Python around a tile, which holds the GIL, is then a small part of it, and threads scale), named by
    their round and a hash of their cells: a rerun asks for the same cells, and loads them.
    """
    Om, b, signs = grid
    chunk = max(1, tile[0] * tile[1])
    shape, coarse, verify = (Om.size, b.size, len(signs)), refinement["coarse"], refinement["verify"]
    refinements = {part: Refinement(shape, coarse, verify) for part in parts}
    total, start, rounds = TileStats(), time.perf_counter(), 0
    where = {}

    def place(task: Task, tile_arrays: dict) -> None:
        part, r, c = where[task.path]
        arrays = with_flew(with_regime(tile_arrays, setting))
        for k in fields:
            fields[k][PARTS.index(part), r, c] = arrays[k]
        over, impacts, status = (arrays[k] for k in ("overturned", "impacts", "status"))
        classes = response_classes(over, impacts, status, arrays.get("regime"), arrays.get("flights"))
        refinements[part].record(r, c, classes)

    while not all(r.done for r in refinements.values()):
        groups = []
        for part, damper in parts.items():
            rows, cols = refinements[part].pending()
            part_tasks = []
            for first in range(0, rows.size, chunk):
                r, c = rows[first : first + chunk], cols[first : first + chunk]
                key = hashlib.sha256(np.stack([r, c]).tobytes()).hexdigest()[:16]
                expect = dict.fromkeys(response_fields(setting), (r.size, len(signs)))
                path = folders[part] / f"round-{rounds}-{key}.npz"
                part_tasks.append(Task(path, cells_tile, (setting, damper, Om[r], b[c], signs), expect))
                where[path] = (part, r, c)
            groups.append(part_tasks)
        tasks = interleave(*groups)
        if tasks:
            try:
                stats = run_tiles(
                    tasks, place, execution, backend=setting.backend, desc=f"map, round {rounds}", on_tile=on_tile
                )
            except Interrupted as exc:  # count the tiles of the rounds before too: all are kept
                done = total.computed + total.reused
                raise Interrupted(done + exc.kept, done + exc.total, exc.folder) from exc
            total.computed, total.reused = total.computed + stats.computed, total.reused + stats.reused
        for part_refinement in refinements.values():
            part_refinement.update()
        rounds += 1
    for index, part_refinement in enumerate(refinements.values()):
        _fill({k: v[index] for k, v in fields.items()}, part_refinement)
    total.wall = time.perf_counter() - start
    return total, rounds, np.stack([r.computed for r in refinements.values()])


def _fill(fields: dict, refinement: Refinement) -> None:
    """Give the cells of one part (``fields``: its arrays ``(Omega, beta, sign)``) that were not computed what
    their class tells: overturned or not, the impacts of a cell that overturned without flying, the status of an
    overturned cell or of one without a verdict, on a floor with friction the regime (``u_max``, ``u_end`` stay NaN
    and ``slides`` :data:`NOT_COMPUTED`), and with a vertical component whether it flew (``flights``,
    ``flight_time``, ``jump_max`` are 0 where it did not, else :data:`NOT_COMPUTED` and NaN)."""
    filled = refinement.fill()
    classes = refinement.classes[filled]  # (cells, signs)
    flew = (classes == FLIES_AND_LANDS_CLASS) | (classes == FLIES_AND_OVERTURNS_CLASS)
    overturned = (classes >= 0) | (classes == FLIES_AND_OVERTURNS_CLASS)
    no_verdict = (classes <= -2) & (classes > -2 - len(STATUS))  # the classes of flights and regimes lie below
    status = np.where(overturned, STATUS.index("overturned"), np.where(no_verdict, -2 - classes, NOT_COMPUTED))
    fields["overturned"][filled] = overturned
    fields["impacts"][filled] = np.where(classes >= 0, classes, NOT_COMPUTED)
    fields["status"][filled] = status
    if "flew" in fields:  # a vertical component: a class with a verdict says whether the base flew
        fields["flew"][filled] = np.where(no_verdict, NOT_COMPUTED, flew)
        grounded = ~no_verdict & ~flew
        for k in FLIGHT_FIELDS:
            fields[k][filled] = np.where(grounded, 0, fields[k][filled])
    if "regime" in fields:  # a floor with friction: what a cell that did not overturn did is its class too
        moved = np.where(classes <= REGIME_CLASS, REGIME_CLASS - classes, NOT_COMPUTED)
        fields["regime"][filled] = np.where(overturned, OVERTURNS, moved)


def half_stroke(block, record: dict) -> float | None:
    """The half-stroke ``L`` (m) of a study's damper (its :meth:`Tuning.record` or :meth:`Variant.record`), or
    None for a guide without stops."""
    if record.get("stops"):
        return record.get("stroke", block.B / 2 - BUMPER_DEPTH)
    return record.get("params", {}).get("L")


def map_tables(data, config: dict) -> dict:
    """The tables of a map (:func:`map_table`), its block and damper read from its configuration."""
    block = Block(**config["block"])
    return {"map": map_table(data, block.B / 2, half_stroke(block, config["damper"]))}


def map_table(data, half_width: float, L: float | None = None) -> dict:
    """One CSV row per cell: the pulse, both responses (their envelope over the directions, and with two
    directions the outcome in each and the sign of the worse), the damper's stroke over the block's
    half-width ``B/2`` (above 1: the mass past the block's edge) and, with stops, over their half-stroke
    ``L`` (above 1: in the bumpers), the damper's effect."""
    env = envelope(data)
    Om, b = np.meshgrid(data["Omega"].values, data["beta"].values, indexing="ij")
    T_g, a_g = np.meshgrid(data["T_g"].values, data["a_g"].values, indexing="ij")
    table = {"Omega": Om, "T_g": T_g, "beta": b, "a_g": a_g}
    signs = data["sign"].values
    for part in PARTS:
        a, by_sign = env.sel(part=part), data.sel(part=part)
        table[f"{part}_outcome"] = outcome(a["overturned"].values, a["impacts"].values)
        for k in ("impacts", "theta_max", "x_max", "stop_contacts", "bumper_force_max"):
            table[f"{part}_{k}"] = a[k].values
        # NOT_COMPUTED (-1) takes the last name; objects, not a wide string array: a map has many cells.
        table[f"{part}_status"] = np.array([*STATUS, "not_computed"], object)[a["status"].values]
        table[f"{part}_computed"] = by_sign["computed"].values.astype(np.int8)
        if signs.size > 1:
            table[f"{part}_worst_sign"] = a["worst_sign"].values
            over, impacts = by_sign["overturned"].values, by_sign["impacts"].values
            for i, sign in enumerate(signs):
                table[f"{part}_outcome_{SIGN_NAMES[sign]}"] = outcome(over[..., i], impacts[..., i])
        if "flew" in env:  # a vertical component: whether the governing response flew, the highest jump
            table[f"{part}_flew"] = a["flew"].values
            table[f"{part}_jump_max"] = a["jump_max"].values
        if "regime" in env:  # a floor with friction: what the pulse did, the larger peak slip of its directions
            table[f"{part}_regime"] = np.array([*REGIMES.values(), "not_computed"], object)[a["regime"].values]
            table[f"{part}_u_max"] = a["u_max"].values
    stroke = env["x_max"].sel(part="damper").values
    table["damper_stroke_over_half_width"] = stroke / half_width
    if L is not None:
        table["damper_stroke_over_L"] = stroke / L
    table["effect"] = env["effect"].values
    return {k: np.ravel(v) for k, v in table.items()}


def saved_past_edges(env, half_width: float) -> np.ndarray:
    """Cells the damper saves only by running its mass past the block's edge: ``x_max > B/2`` (``env``: a map's
    :func:`envelope`).

    An unlimited guide (the paper's) lets the mass travel anywhere; a real one ends at the
    block's edges (docs/model.md section 11), so these cells are saved on paper only.
    """
    return (env["effect"].values > 0) & (env["x_max"].sel(part="damper").values > half_width)


def map_summary(data, half_width: float) -> dict:
    """Cell counts: overturned per part, saved and lost by the damper (saved within the block's half-width
    ``B/2`` or only past it), runs that hit ``t_max`` or a bound, cells computed, and what of them is inferred;
    with a vertical component the cells whose governing response flew and landed without overturning
    (``{part}_flies_and_lands``) or flew and overturned (``{part}_flies_and_overturns``).

    Counts of what a cell's outcome class does not tell (``t_max``, ``saved_past_edges``) are over the cells
    computed; ``saved_stroke_not_computed`` counts the saved cells whose damper stroke was not computed.
    The cells an adaptive map did not compute took the class around them (:mod:`rocking.study.adaptive`), which
    a region thinner than its guarantee can belie: :func:`inferred_counts` says how much of each count rests
    on them, and how much more they could hold.
    """
    env = envelope(data)
    effect = env["effect"].values
    out = {"cells": int(effect.size)}
    for part in PARTS:
        a, status = env.sel(part=part), env["status"].sel(part=part).values
        out[f"{part}_computed"] = int(data["computed"].sel(part=part).values.sum())
        out[f"{part}_overturned"] = int(a["overturned"].values.sum())
        out[f"{part}_t_max"] = int((status == STATUS.index("t_max")).sum())
        out[f"{part}_undetermined"] = int(undetermined(status).sum())
        if "regime" in env:  # a floor with friction: the cells where the base slid (and did not overturn)
            out[f"{part}_slid"] = int(np.isin(env["regime"].sel(part=part).values, SLID).sum())
        if "flew" in env:  # a vertical component: the cells whose governing response flew to a verdict, and how
            flew = (env["flew"].sel(part=part).values == 1) & ~undetermined(status)
            out[f"{part}_flies_and_lands"] = int((flew & ~a["overturned"].values).sum())
            out[f"{part}_flies_and_overturns"] = int((flew & a["overturned"].values).sum())
    out["saved"] = int((effect > 0).sum())
    out["saved_past_edges"] = int(saved_past_edges(env, half_width).sum())
    out["saved_stroke_not_computed"] = int(((effect > 0) & ~data["computed"].sel(part="damper").values).sum())
    out["lost"] = int((effect < 0).sum())
    return {**out, **inferred_counts(data, env)}


def inferred_counts(data, env) -> dict:
    """How much of a map's counts rests on cells not computed (``data["computed"]``; ``env`` its
    :func:`envelope`), and how much more those cells could hold were their classes other than inferred.

    Returns
    -------
    dict of int
        ``{part}_inferred``: the cells of each part not computed; ``{part}_overturned_inferred``: of them, those
        counted overturned; ``saved_inferred``, ``lost_inferred``: the cells counted saved (lost) of which a part
        was not computed; ``saved_possible``, ``lost_possible``: the cells not counted saved (lost) that would
        be, were the class of their parts not computed another (an upper bound: every such cell). All 0 for a
        map that computed every cell.
    """
    computed = {p: data["computed"].sel(part=p).transpose("Omega", "beta").values for p in PARTS}
    over = {p: env["overturned"].sel(part=p).values for p in PARTS}
    effect = env["effect"].values
    inferred = ~computed["bare"] | ~computed["damper"]
    out = {}
    for part in PARTS:
        out[f"{part}_inferred"] = int((~computed[part]).sum())
        out[f"{part}_overturned_inferred"] = int((over[part] & ~computed[part]).sum())
    # Whether each part could be overturned, or safe, given what was computed.
    could_over = {p: over[p] | ~computed[p] for p in PARTS}
    could_safe = {p: ~over[p] | ~computed[p] for p in PARTS}
    for name, counted, possible in (
        ("saved", effect > 0, could_over["bare"] & could_safe["damper"]),
        ("lost", effect < 0, could_safe["bare"] & could_over["damper"]),
    ):
        out[f"{name}_inferred"] = int((counted & inferred).sum())
        out[f"{name}_possible"] = int((~counted & inferred & possible).sum())
    return out
