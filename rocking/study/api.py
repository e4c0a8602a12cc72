"""The studies with plain arguments, returning labelled data: ``rocking.overturning_map`` and its kin.

Each function takes a :class:`~rocking.model.params.Block` (the threshold map: ranges of
geometries), the damper as a :class:`~rocking.study.config.Tuning` or a mapping of its keywords
(``gamma``, ``omega_ratio``, ``zeta``, ``h``, ``stops``), the swept quantities as arrays of values
(or :class:`~rocking.study.config.Grid`), and the solver and execution options as keywords; it runs
the study of :mod:`rocking.study` (tiles kept under ``runs``: a rerun loads them) and returns its
:class:`xarray.Dataset` (:mod:`rocking.study.dataset`). ``study=True`` returns the
:class:`~rocking.study.config.Study` instead, for :func:`rocking.save` and the figures.

The keywords every function shares:

rtol, t_after, backend
    Relative tolerance of the integrator, time followed after the excitation (s), ``"c"`` or
    ``"numpy"`` (:class:`~rocking.study.config.Setting`).
pulse, gamma_mp, nu
    The pulse family of the pulse studies: ``"sine"`` (the paper's), ``"cosine"``, ``"ricker"``, ...,
    ``"mp"`` with its oscillations ``gamma_mp`` (> 1) and phase ``nu`` (rad).
Omega, beta or T_g, a_g
    The pulses of the maps, spectra and designs: frequency and amplitude ratios ``omega_g / p`` and
    ``a_g / (g tan alpha)``, or in their place periods ``T_g = 2 pi / omega_g`` (s) and amplitudes ``a_g``
    (m/s^2), as arrays or :class:`~rocking.study.config.Grid` (:func:`rocking.study.config.pulse_grids`;
    docs/model.md section 9). Each quantity one way: ``Omega`` or ``T_g``, ``beta`` or ``a_g``.
mu, mu_k, e_n
    The floor of every response, ``rocking.Floor(mu, mu_k, e_n)`` (:class:`~rocking.study.config.Setting`,
    docs/model.md sections 15 and 16): static and kinetic Coulomb friction, dimensionless, and the normal
    restitution of a landing after flight, in [0, 1]; default ``None``: the paper's floor, on which the base
    never slides, with plastic landings (``e_n = 0``). Only a back end that follows friction runs a finite one.
vertical_ratio, vertical_phase
    The maps' and spectra's vertical component of every pulse, ``rocking.Vertical(vertical_ratio,
    vertical_phase)`` (:class:`~rocking.study.config.Setting`, docs/model.md section 14): ratio in [0, 10]
    (default 0: none), lead in [0, 2 pi) rad.
workers, scheduler, dask_workers, progress
    Local workers (default: all cores), a Dask scheduler's address or a local Dask cluster of that many
    workers, and a progress bar (:class:`~rocking.study.tiles.Execution`).
runs
    Folder of the finished tiles; default :func:`runs_folder`, a per-user cache (the command line's is
    ``OUT/runs``, under its ``--out``). The progress bar names it.
study
    Return the :class:`~rocking.study.config.Study`, not its ``Dataset``.

Each option of a study command of the command line is a keyword of its function here, by the same
name (``--gamma-mp`` is ``gamma_mp=``, ``--beta-tol`` is ``beta_tol=``); the options that build one
object are given as that object or a mapping of its keywords: the block's (``--H``, ``--p``, ...) as
``block``, the damper's (``--gamma``, ``--Tm-ratio``, ...) as ``damper``, the stochastic site model's
(``--arias``, ...) as ``site``. Only ``--out``, ``--no-progress`` (``progress=False``) and
``--config`` (a rerun of a saved study) are the command line's own.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import platformdirs

from ..model.floor import Floor, floor_of
from ..model.params import Block, Damper, ParameterError, check_block
from .config import Grid, Setting, Tuning, Variant, pulse_grids, tm_omega_ratio
from .design import REFINE
from .design import design as _design
from .friction_map import TILE as FRICTION_TILE
from .friction_map import friction_map as _friction_map
from .ida import LEVELS
from .ida import incremental_dynamic_analysis as _incremental_dynamic_analysis
from .optimize import REFINE as OPTIMIZE_REFINE
from .optimize import optimal_damper as _optimal_damper
from .overturning_map import COARSE, TILE
from .overturning_map import overturning_map as _overturning_map
from .spectrum import TOL
from .spectrum import minimum_overturning_spectrum as _minimum_overturning_spectrum
from .suite import suite_of
from .threshold import A_MAX
from .threshold import threshold_map as _threshold_map
from .tiles import Execution

#: The application's name of :func:`runs_folder`'s per-user cache.
APP = "rocking"


def runs_folder() -> Path:
    """Where the tiles of a study called from Python are kept unless ``runs=`` says otherwise: the user's cache of
    the platform (``~/.cache/rocking/runs`` on Linux, ``~/Library/Caches/rocking/runs`` on macOS,
    ``%LOCALAPPDATA%\\rocking\\Cache\\runs`` on Windows; ``platformdirs.user_cache_dir``), not the current folder,
    which a notebook would fill unasked. Deleting it costs only recomputation."""
    return Path(platformdirs.user_cache_dir(APP, appauthor=False)) / "runs"


def _setting(
    block, rtol: float, t_after: float, backend: str, pulse: str = "sine", gamma_mp=None, nu=None, *, floor, **vertical
):
    """The study's :class:`Setting`; ``floor``: ``(mu, mu_k, e_n)``; ``vertical``: ``vertical_ratio`` and
    ``vertical_phase`` of the maps and spectra."""
    shape = {"gamma_mp": gamma_mp} | ({} if nu is None else {"nu": nu})
    return Setting(
        check_block(block),
        rtol=rtol,
        t_after=t_after,
        backend=backend,
        pulse=pulse,
        floor=_floor(*floor),
        **shape,
        **vertical,
    )


def _floor(mu, mu_k, e_n=None) -> Floor:
    """The :class:`Floor` of a study's ``mu``, ``mu_k`` (:func:`rocking.model.floor.floor_of`) and ``e_n`` (None:
    plastic)."""
    floor = floor_of(None, mu, mu_k)
    return floor if e_n is None else Floor(floor.mu_s, floor.mu_k, e_n)


def _tuning(damper) -> Tuning | Variant:
    """A study's damper from None (the default Tuning), a Tuning, a Variant, a built :class:`~rocking.Damper` (with
    its :class:`~rocking.Stops`: the :class:`Variant` of its model and parameters, as :func:`rocking.simulate` runs
    it), or a mapping of Tuning's keywords."""
    if damper is None:
        return Tuning()
    if isinstance(damper, Tuning | Variant):
        return damper
    if isinstance(damper, Damper):
        if damper.m == 0.0:
            raise ParameterError("damper: a Damper of mass m = 0 is the block alone, which every study runs anyway")
        return Variant(damper.model, damper.as_params())
    if isinstance(damper, Mapping):
        try:
            return Tuning(**with_omega_ratio(damper))
        except TypeError as exc:
            raise ParameterError(
                f"damper: {exc} (keywords of rocking.Tuning: gamma, omega_ratio or Tm_ratio, zeta, h, stops)"
            ) from None
    raise ParameterError(
        f"damper must be a rocking.Tuning, a rocking.Damper, a rocking.Variant or a mapping such as {{'gamma': 0.05}} "
        f"(got {type(damper).__name__})"
    )


def with_omega_ratio(values: Mapping) -> dict:
    """Keywords of :class:`Tuning` with ``Tm_ratio`` (the damper's period ``T_m p / (2 pi)``, the command line's
    ``--Tm-ratio``) given as its ``omega_ratio = 1 / Tm_ratio`` (:func:`rocking.study.config.tm_omega_ratio`)."""
    values = dict(values)
    if "Tm_ratio" not in values:
        return values
    if "omega_ratio" in values:
        raise ParameterError("give the damper's Tm_ratio or its omega_ratio = 1 / Tm_ratio, not both")
    return {**values, "omega_ratio": tm_omega_ratio(values.pop("Tm_ratio"))}


def _grid(name: str, values) -> Grid | None:
    if values is None or isinstance(values, Grid):
        return values
    return Grid.of(name, values)


def _pulse_grids(block: Block, Omega, beta, T_g, a_g) -> tuple[Grid, Grid]:
    """The ``Omega`` and ``beta`` grids of a study of pulses, each given as ratios or in SI units
    (:func:`rocking.study.config.pulse_grids`)."""
    grids = pulse_grids(block, _grid("Omega", Omega), _grid("beta", beta), _grid("T_g", T_g), _grid("a_g", a_g))
    return grids["Omega"], grids["beta"]


def _run(study_function, *args, workers, scheduler, dask_workers, progress: bool, runs, study: bool, **keywords):
    """``study_function(*args, execution, runs=runs, **keywords)``; its Study if ``study``, else its Dataset."""
    execution = Execution(workers=workers, scheduler=scheduler, dask_workers=dask_workers, progress=progress)
    runs = runs_folder() if runs is None else Path(runs)
    if progress:
        # Beside the progress bar, on stderr: a study called from a notebook says where its tiles go.
        print(f"rocking.{study_function.__name__}: tiles kept in {runs} (runs= to choose)", file=sys.stderr)
    result = study_function(*args, execution, runs=runs, **keywords)
    return result if study else result.to_dataset()


def overturning_map(
    block: Block,
    damper=None,
    *,
    Omega=None,
    beta=None,
    T_g=None,
    a_g=None,
    directions: str = "auto",
    full: bool = False,
    coarse: int = COARSE,
    verify: int | None = None,
    tile: tuple[int, int] = TILE,
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    gamma_mp: float | None = None,
    nu: float | None = None,
    vertical_ratio: float = Setting.vertical_ratio,
    vertical_phase: float = Setting.vertical_phase,
    mu: float | None = None,
    mu_k: float | None = None,
    e_n: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
):
    """The overturning map of ``block`` alone and with ``damper`` over ``Omega x beta``.

    Parameters
    ----------
    block : Block
    damper : Tuning, Damper, Variant or mapping, optional
        Default ``Tuning()`` (gamma 0.05, omega_ratio 1, zeta 0.05, h 0.05 m). A built :class:`~rocking.Damper`
        (with its :class:`~rocking.Stops`, e.g. :func:`rocking.designed_damper` of a design) runs as it is.
    Omega, beta : array_like or Grid
        Pulse frequency ratios ``omega_g / p`` and amplitude ratios ``a_g / (g tan alpha)``, increasing.
    T_g, a_g : array_like or Grid, optional
        In place of ``Omega`` and ``beta``: pulse periods ``T_g`` (s) and amplitudes ``a_g`` (m/s^2).
    directions, full, coarse, verify, tile
        As :func:`rocking.study.overturning_map.overturning_map`.
    rtol, t_after, pulse, gamma_mp, nu, mu, mu_k, e_n, backend, workers, scheduler, dask_workers, runs, progress, study
        Shared by every study (:mod:`rocking.study.api`).
    vertical_ratio, vertical_phase : float, optional
        The vertical component of every pulse (:mod:`rocking.study.api`); default none.

    Returns
    -------
    xarray.Dataset
        Every response, dimensions ``part`` (``bare``, ``damper``), ``Omega``, ``beta``, ``sign``; their
        envelope over the directions and the damper's effect: :func:`rocking.study.overturning_map.envelope`.

    Examples
    --------
    >>> import tempfile, numpy as np, rocking
    >>> ds = rocking.overturning_map(rocking.Block.reference(), {"gamma": 0.05}, Omega=[2.0, 4.0, 6.0],
    ...                              beta=np.linspace(1, 6, 4), runs=tempfile.mkdtemp(), progress=False)
    >>> ds["overturned"].dims, ds["a_g"].attrs["units"]
    (('part', 'Omega', 'beta', 'sign'), 'm/s^2')
    >>> from rocking.study.overturning_map import envelope
    >>> int(envelope(ds)["effect"].sum())  # cells saved by the damper minus cells lost
    0
    """
    return _run(
        _overturning_map,
        _setting(
            block,
            rtol,
            t_after,
            backend,
            pulse,
            gamma_mp,
            nu,
            floor=(mu, mu_k, e_n),
            vertical_ratio=vertical_ratio,
            vertical_phase=vertical_phase,
        ),
        _tuning(damper),
        *_pulse_grids(check_block(block), Omega, beta, T_g, a_g),
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        directions=directions,
        full=full,
        coarse=coarse,
        verify=verify,
        tile=tuple(tile),
    )


def friction_map(
    block: Block,
    damper=None,
    *,
    Omega=None,
    T_g=None,
    mu,
    beta=None,
    a_g=None,
    directions: str = "auto",
    tile: tuple[int, int] = FRICTION_TILE,
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    gamma_mp: float | None = None,
    nu: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
):
    """The regime map of ``block`` (alone, or with ``damper``) over floors ``mu`` and pulse amplitudes, at one
    pulse frequency (:mod:`rocking.study.friction_map`, Shenton 1996's regime charts).

    Parameters
    ----------
    block : Block
    damper : Tuning, Damper, Variant or mapping, optional
        The damper on the block; default ``None``: the block alone.
    Omega : float
        The pulses' frequency ratio ``omega_g / p``; or ``T_g``, their period (s).
    mu : array_like or Grid
        The floors' Coulomb friction, static = kinetic (``rocking.Floor(mu)``), increasing, > 0.
    beta : array_like or Grid
        Pulse amplitude ratios ``a_g / (g tan alpha)``, increasing; or ``a_g``, amplitudes (m/s^2).
    directions, tile
        As :func:`rocking.study.friction_map.friction_map`.
    rtol, t_after, pulse, gamma_mp, nu, backend, workers, scheduler, dask_workers, runs, progress, study
        Shared by every study (:mod:`rocking.study.api`); both back ends follow friction: default ``"c"``.

    Returns
    -------
    xarray.Dataset
        Every response, dimensions ``mu``, ``beta``, ``sign``: its ``regime`` (rest, rocks, slides, slides and
        rocks, overturns), ``u_max``, ``u_end`` (m), ``theta_max`` (rad), ...; both directions together:
        :func:`rocking.study.friction_map.envelope`.

    Examples
    --------
    >>> import tempfile, rocking
    >>> ds = rocking.friction_map(rocking.Block(2.0, 0.5, 1000.0), T_g=0.5, mu=[0.15, 0.5], a_g=[3.0, 4.0],
    ...                           runs=tempfile.mkdtemp(), progress=False, workers=1)
    >>> ds["regime"].attrs["flag_meanings"]
    'not_computed rest rocks slides slides_and_rocks overturns'
    >>> ds["regime"].sel(sign=1).values  # rows: mu, columns: a_g; 2 slides, 1 rocks
    array([[2, 2],
           [1, 1]])
    """
    # One frequency, given as a ratio or a period: a grid of one value, checked and converted as the maps' are.
    one = {k: None if v is None else Grid.of(k, np.atleast_1d(v)) for k, v in (("Omega", Omega), ("T_g", T_g))}
    grids = pulse_grids(check_block(block), one["Omega"], _grid("beta", beta), one["T_g"], _grid("a_g", a_g))
    return _run(
        _friction_map,
        _setting(block, rtol, t_after, backend, pulse, gamma_mp, nu, floor=(None, None)),
        float(grids["Omega"].values()[0]),
        _grid("mu", mu),
        grids["beta"],
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        damper=None if damper is None else _tuning(damper),
        directions=directions,
        tile=tuple(tile),
    )


def minimum_overturning_spectrum(
    block: Block,
    damper=None,
    *,
    Omega=None,
    beta=None,
    T_g=None,
    a_g=None,
    beta_tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    gamma_mp: float | None = None,
    nu: float | None = None,
    vertical_ratio: float = Setting.vertical_ratio,
    vertical_phase: float = Setting.vertical_phase,
    mu: float | None = None,
    mu_k: float | None = None,
    e_n: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
):
    """The minimum overturning amplitude ``beta_min(Omega)`` of ``block`` alone and with ``damper``.

    ``beta`` are the scan amplitudes, every one computed (their step bounds the safe windows and the overturning
    bands seen, :mod:`rocking.study.spectrum`); ``beta_tol`` the relative tolerance of the bisection. Other
    parameters as :func:`overturning_map`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``part`` (``bare``, ``damper``), ``Omega``, ``sign``, ``beta_scan``; ``flag`` says which
        ``beta_min`` are bounds; their envelope over the directions: :func:`rocking.study.spectrum.envelope`.

    Examples
    --------
    >>> import tempfile, rocking
    >>> ds = rocking.minimum_overturning_spectrum(rocking.Block.reference(), None, Omega=[2.0, 6.0],
    ...                                           beta=[0.5, 2, 4, 8, 15], runs=tempfile.mkdtemp(), progress=False)
    >>> both = rocking.study.spectrum.envelope(ds)
    >>> both["beta_min"].sel(part="bare").round(2).values.tolist(), both["flag"].attrs["flag_meanings"]
    ([1.15, 2.82], 'upper_bound bracketed lower_bound')
    """
    return _run(
        _minimum_overturning_spectrum,
        _setting(
            block,
            rtol,
            t_after,
            backend,
            pulse,
            gamma_mp,
            nu,
            floor=(mu, mu_k, e_n),
            vertical_ratio=vertical_ratio,
            vertical_phase=vertical_phase,
        ),
        _tuning(damper),
        *_pulse_grids(check_block(block), Omega, beta, T_g, a_g),
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        tol=beta_tol,
        directions=directions,
    )


def optimal_damper(
    block: Block,
    gammas,
    *,
    Omega,
    beta,
    zeta: float = Tuning.zeta,
    h: float = Tuning.h,
    stops: bool = False,
    Tm_ratio=None,
    refine: int = OPTIMIZE_REFINE,
    beta_tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    gamma_mp: float | None = None,
    nu: float | None = None,
    mu: float | None = None,
    mu_k: float | None = None,
    e_n: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
):
    """The damper period that most raises ``beta_min``, for each mass ratio of ``gammas``, against ``Omega``.

    ``Tm_ratio``: the coarse damper periods ``T_m p / (2 pi)`` searched, values > 0 or a logarithmic :class:`Grid`
    (default that of :func:`rocking.study.optimize.optimal_damper`), ``refine`` points each side of the best.
    Other parameters as :func:`minimum_overturning_spectrum`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``gamma``, ``Omega``, ``sign``, ``r_coarse``, ...: the gain and the optimal damper in SI units.

    Examples
    --------
    >>> import tempfile, rocking
    >>> ds = rocking.optimal_damper(rocking.Block.reference(), [0.05], Omega=[4.0], beta=[0.5, 2, 4, 8, 15],
    ...                             Tm_ratio=rocking.Grid("Tm_ratio", 0.5, 2.0, 3, log=True),
    ...                             runs=tempfile.mkdtemp(), progress=False)
    >>> ds["k_m_opt"].attrs["units"], bool(ds["gain_opt"].sel(gamma=0.05, Omega=4.0) > 0)
    ('N/m', True)
    """
    return _run(
        _optimal_damper,
        _setting(block, rtol, t_after, backend, pulse, gamma_mp, nu, floor=(mu, mu_k, e_n)),
        gammas,
        _grid("Omega", Omega),
        _grid("beta", beta),
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        zeta=zeta,
        h=h,
        stops=stops,
        Tm=_grid("Tm_ratio", Tm_ratio),
        refine=refine,
        tol=beta_tol,
        directions=directions,
    )


def design(
    block: Block,
    *,
    Omega=None,
    beta=None,
    T_g=None,
    a_g=None,
    gamma: float = Tuning.gamma,
    stroke: float | None = None,
    h: float = Tuning.h,
    Tm_ratio=None,
    zeta_grid=None,
    refine: int = REFINE,
    beta_tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    gamma_mp: float | None = None,
    nu: float | None = None,
    mu: float | None = None,
    mu_k: float | None = None,
    e_n: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
):
    """The damper with stops, of mass ``gamma M`` and half-stroke ``stroke`` (m), that most raises the worst
    ``beta_min`` over the band ``Omega`` in both directions.

    ``Tm_ratio`` and ``zeta_grid``: the coarse damper periods ``T_m p / (2 pi)`` and damping ratios searched
    (arrays of values > 0 or log :class:`Grid`; defaults those of :func:`rocking.study.design.design`),
    ``refine`` points each side of the best. Other parameters as :func:`minimum_overturning_spectrum`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``part``, ``Omega``, ``sign``, ``candidate``, ...; the damper in SI units in the attribute
        ``summary`` (JSON) and in the variables ``gain_opt``, ``stroke_use``, ``bumper_force_max`` (N).
        What it achieved in the attributes ``verdict`` (``"helps"``, ``"no_useful_gain"``, ``"harms"``,
        ``"undefined"``) and ``verdict_text``; the damper built, with its stops, for :func:`rocking.simulate` and
        every study's ``damper``: :func:`rocking.designed_damper`.

    Warns
    -----
    DesignWarning
        The design does not help over the band: the verdict's sentence, as the command line prints it.
    rocking.study.optimize.EdgeWarning
        The optimal ``Tm_ratio`` or ``zeta`` is an end of its search range: widen it.

    Examples
    --------
    >>> import json, tempfile, numpy as np, rocking
    >>> ds = rocking.design(rocking.Block.reference(), Omega=[4.0, 6.0], beta=np.linspace(0.5, 20.0, 27),
    ...                     Tm_ratio=np.geomspace(0.5, 4.0, 3), zeta_grid=[0.02, 0.2], refine=1,
    ...                     runs=tempfile.mkdtemp(), progress=False)
    >>> damper = json.loads(ds.attrs["summary"])["damper"]
    >>> round(damper["m_kg"]), round(damper["k_m_N_per_m"], 1)  # kg, N/m
    (50, 22.3)
    """
    return _run(
        _design,
        _setting(block, rtol, t_after, backend, pulse, gamma_mp, nu, floor=(mu, mu_k, e_n)),
        *_pulse_grids(check_block(block), Omega, beta, T_g, a_g),
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        gamma=gamma,
        stroke=stroke,
        h=h,
        Tm=_grid("Tm_ratio", Tm_ratio),
        zeta=_grid("zeta", zeta_grid),
        refine=refine,
        tol=beta_tol,
        directions=directions,
    )


def threshold_map(
    *,
    lam,
    p,
    Omega,
    e_ratio: float = 0.05,
    gamma: float = Tuning.gamma,
    zeta: float = Tuning.zeta,
    h: float = Tuning.h,
    Tm_ratio=None,
    refine: int = 1,
    a_max: float = A_MAX,
    beta_tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
):
    """The threshold frequency ``Omega*`` above which the damper helps, over block geometries ``lam x p``.

    Parameters
    ----------
    lam, p : array_like or Grid
        Slenderness ``H / B`` and size ``p`` (rad/s) of the blocks, each of eccentricity ``e_ratio`` (``e / B``).
    Omega : array_like or Grid
        Pulse frequency ratios scanned at each geometry.
    gamma, zeta, h, Tm_ratio, refine
        The damper (unlimited, and with stops at the block's edges): mass ratio, damping ratio, guide height
        (m); its periods ``T_m p / (2 pi)`` searched (arrays of values > 0 or a log Grid) and refined.
    a_max : float
        Bound of the ground acceleration, in g.
    beta_tol, directions, rtol, t_after, backend, workers, scheduler, dask_workers, runs, progress, study
        As :func:`minimum_overturning_spectrum`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``part`` (``unlimited``, ``stops``), ``lam``, ``p``, ``Omega``, ...: the gains; ``Omega*`` and its
        status per geometry: :func:`rocking.study.threshold.thresholds`.

    Examples
    --------
    >>> import tempfile, rocking
    >>> ds = rocking.threshold_map(lam=[4.0], p=[2.0], Omega=[4.0, 9.0, 14.0], Tm_ratio=[0.5, 2.0], refine=0,
    ...                            runs=tempfile.mkdtemp(), progress=False)
    >>> ds["gain"].sel(part="stops", lam=4.0, p=2.0).round(2).values.tolist()  # none at 14: safe to 4 g alone
    [1.14, 1.41, nan]
    """
    return _run(
        _threshold_map,
        _grid("lam", lam),
        _grid("p", p),
        _grid("Omega", Omega),
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        e_ratio=e_ratio,
        gamma=gamma,
        zeta=zeta,
        h=h,
        Tm=_grid("Tm_ratio", Tm_ratio),
        refine=refine,
        a_max=a_max,
        tol=beta_tol,
        rtol=rtol,
        t_after=t_after,
        backend=backend,
        directions=directions,
    )


def _ida(
    measure: str,
    block: Block,
    damper,
    levels,
    suite: dict,
    *,
    directions: str,
    rtol: float,
    t_after: float,
    floor: tuple,
    backend: str,
    workers,
    scheduler,
    dask_workers,
    runs,
    progress: bool,
    study: bool,
    check: str | None,
):
    """The study of :func:`incremental_dynamic_analysis` (``measure="scale"``) or of :func:`fragility`."""
    setting = _setting(block, rtol, t_after, backend, floor=floor)
    return _run(
        _incremental_dynamic_analysis,
        setting,
        _tuning(damper),
        suite_of(**suite, g=setting.block.g),
        _grid("levels", levels),
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        progress=progress,
        runs=runs,
        study=study,
        measure_name=measure,
        directions=directions,
        check=check,
    )


def incremental_dynamic_analysis(
    block: Block,
    damper=None,
    *,
    scales,
    motions=None,
    unit: str | None = None,
    vertical_motions=None,
    stochastic: int | None = None,
    seed: int | None = None,
    site=None,
    vertical_ratio: float | None = None,
    vertical_site=None,
    pulses: str | None = None,
    periods=None,
    amplitude: float | None = None,
    gamma_mp: float | None = None,
    nu: float | None = None,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    mu: float | None = None,
    mu_k: float | None = None,
    e_n: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
    check: str | None = None,
):
    """Every motion of a suite at every scale factor of ``scales``, with and without ``damper``; the lognormal
    fitted to the outcomes against the scale factor.

    Parameters
    ----------
    scales : array_like or Grid
        Scale factors of every motion, increasing.
    motions : Suite, record files, or pulses
        Record files (PEER ``.AT2``, two-column text, ...): paths, or ``(path, unit)`` pairs for a file's own unit
        (``"g"``, ``"m/s2"``, ``"cm/s2"``); ``unit``: that of the others (default: the one each header states);
        pulses (:class:`rocking.OneSinePulse`, :class:`rocking.RickerWavelet`, ...) or a :class:`rocking.Suite`.
    vertical_motions : record files, optional
        With record files: the vertical record of each, in the same order (paths, or ``(path, unit)`` pairs;
        ``unit`` for the others), > 0 up, of its horizontal record's dt, taken as 0 after its end and cut at the
        horizontal record's end, as ``rocking simulate --motion H --vertical V``; hashed like the horizontal
        files. A scale factor scales both components (:meth:`rocking.study.suite.Suite.from_files`,
        docs/model.md section 14).
    stochastic, seed, site
        Instead: ``stochastic`` motions of the site model ``site`` (a
        :class:`~rocking.model.stochastic.SiteModel` or a mapping of its keywords, ``arias``, ``d595``, ...,
        over the defaults) from ``seed`` (default 0).
    vertical_ratio, vertical_site
        With ``stochastic``: each motion's vertical component, ``vertical_ratio`` (in [0, 10]) times a record of
        ``vertical_site`` (a SiteModel or a mapping of its keywords over ``site``'s; default ``site``) of its own
        noise, > 0 up (:meth:`rocking.study.suite.Suite.stochastic`, docs/model.md section 14).
    pulses, periods, amplitude, gamma_mp, nu
        Instead: a family of pulses (``"sine"``, ``"ricker"``, ``"mp"``, ...), one per period (s), of
        amplitude ``amplitude`` (m/s^2, default 1 g) and the MP shape (:func:`rocking.study.suite.of_pulses`).
    damper, directions, rtol, t_after, mu, mu_k, e_n, backend, workers, scheduler, dask_workers, runs, progress, study
        As :func:`overturning_map`.
    check : {"tolerance", "none"}, optional
        The tolerance check of every response, as :func:`rocking.simulate`'s (docs/simulation.md,
        "Sensitivity to the tolerance"): by default ``"tolerance"`` for records and stochastic motions,
        ``"none"`` for pulses.

    Returns
    -------
    xarray.Dataset
        Dimensions ``part`` (``bare``, ``damper``), ``motion`` (the motions' names), ``level``, ``sign``; the
        fitted curves at ``curve_x``; per part the fit (``median``, ``dispersion``, their ``_low``/``_high``
        90 % intervals, ``fit_status``) and per part and motion what each motion shows (``first``, ``last_safe``,
        ``reversals``, ``sensitive_responses``): :func:`rocking.study.ida.incremental_dynamic_analysis`; the
        envelope over the directions: :func:`rocking.study.ida.envelope`.

    Examples
    --------
    >>> import tempfile, rocking
    >>> ds = rocking.incremental_dynamic_analysis(rocking.Block.reference(), {"gamma": 0.05}, pulses="ricker",
    ...                                           periods=[0.5, 1.0], amplitude=3.0, scales=[1.0, 2.0],
    ...                                           runs=tempfile.mkdtemp(), progress=False)
    >>> ds["motion"].values.tolist(), ds["level"].attrs["units"]
    (['ricker-T0.5-0', 'ricker-T1-1'], '1')
    """
    suite = {"motions": motions, "unit": unit, "vertical_motions": vertical_motions, "stochastic": stochastic}
    suite |= {"seed": seed, "site": site}
    suite |= {"vertical_ratio": vertical_ratio, "vertical_site": vertical_site}
    suite |= {"pulses": pulses, "periods": periods, "amplitude": amplitude, "gamma_mp": gamma_mp, "nu": nu}
    return _ida(
        "scale",
        block,
        damper,
        scales,
        suite,
        directions=directions,
        rtol=rtol,
        t_after=t_after,
        floor=(mu, mu_k, e_n),
        backend=backend,
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        runs=runs,
        progress=progress,
        study=study,
        check=check,
    )


def fragility(
    block: Block,
    damper=None,
    *,
    levels,
    im: str = "pga",
    motions=None,
    unit: str | None = None,
    vertical_motions=None,
    stochastic: int | None = None,
    seed: int | None = None,
    site=None,
    vertical_ratio: float | None = None,
    vertical_site=None,
    pulses: str | None = None,
    periods=None,
    amplitude: float | None = None,
    gamma_mp: float | None = None,
    nu: float | None = None,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    mu: float | None = None,
    mu_k: float | None = None,
    e_n: float | None = None,
    backend: str = "c",
    workers: int | None = None,
    scheduler: str | None = None,
    dask_workers: int | None = None,
    runs: str | Path | None = None,
    progress: bool = True,
    study: bool = False,
    check: str | None = None,
):
    """The fragility of ``block`` alone and with ``damper``: every motion of a suite scaled to every level of the
    intensity measure ``im``, and the lognormal fitted to the outcomes (median and dispersion).

    Parameters
    ----------
    levels : array_like or Grid
        Levels of the intensity measure in its SI unit, increasing.
    im : {"pga", "pgv", "arias", "cav", "amplitude"}
        The intensity measure: PGA (m/s^2), PGV (m/s), Arias intensity (m/s), CAV (m/s), or the amplitude
        ``a_g`` of a suite of pulses (m/s^2).
    motions, unit, vertical_motions, stochastic, seed, site, vertical_ratio, vertical_site
        The suite, as :func:`incremental_dynamic_analysis`. A level scales a motion with a vertical component, both
        components by the same factor, to the level of the measure of its horizontal component: the measures are
        the horizontal record's.
    pulses, periods, amplitude, gamma_mp, nu, check
        As :func:`incremental_dynamic_analysis`.
    damper, directions, rtol, t_after, mu, mu_k, e_n, backend, workers, scheduler, dask_workers, runs, progress, study
        As :func:`overturning_map`.

    Returns
    -------
    xarray.Dataset
        As :func:`incremental_dynamic_analysis`'s, ``level`` in the unit of ``im``; the fit's ``median`` (in the
        unit of ``im``) and ``dispersion`` per part.

    Warns
    -----
    FitWarning
        A lognormal fitted to fewer than 10 motions, or of a dispersion below 0.05
        (:func:`rocking.study.fragility.fit_warnings`, which says why); or whose median lies above the highest
        level tested or below the lowest (extrapolated: the median, that level and the fraction overturned there;
        ``median_extrapolated`` per part marks it, :func:`rocking.study.fragility.median_words`).

    Examples
    --------
    >>> import tempfile, rocking
    >>> block = rocking.Block.reference()
    >>> pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.5, 1.0, 2.0)]  # a_g 3 m/s^2, T_g in s
    >>> ds = rocking.fragility(block, {"gamma": 0.05}, motions=pulses, levels=[1.0, 2.0, 4.0], im="amplitude",
    ...                       runs=tempfile.mkdtemp(), progress=False)
    >>> ds["fraction"].dims, ds["level"].attrs["units"]
    (('part', 'level'), 'm/s^2')
    """
    if im not in tuple(LEVELS)[1:]:
        raise ParameterError(f"im must be one of {', '.join(tuple(LEVELS)[1:])} (got {im!r})")
    suite = {"motions": motions, "unit": unit, "vertical_motions": vertical_motions, "stochastic": stochastic}
    suite |= {"seed": seed, "site": site}
    suite |= {"vertical_ratio": vertical_ratio, "vertical_site": vertical_site}
    suite |= {"pulses": pulses, "periods": periods, "amplitude": amplitude, "gamma_mp": gamma_mp, "nu": nu}
    return _ida(
        im,
        block,
        damper,
        levels,
        suite,
        directions=directions,
        rtol=rtol,
        t_after=t_after,
        floor=(mu, mu_k, e_n),
        backend=backend,
        workers=workers,
        scheduler=scheduler,
        dask_workers=dask_workers,
        runs=runs,
        progress=progress,
        study=study,
        check=check,
    )
