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
pulse
    The pulse family of the pulse studies: ``"sine"`` (the paper's), ``"cosine"``, ``"ricker"``, ...
workers, progress
    Local workers (default: all cores) and a progress bar (:class:`~rocking.study.tiles.Execution`).
runs
    Folder of the finished tiles (default ``out/runs``, as the command line's).
study
    Return the :class:`~rocking.study.config.Study`, not its ``Dataset``.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

from ..model.params import Block, ParameterError, check_block
from .config import Grid, Setting, Tuning, Variant
from .design import REFINE
from .design import design as _design
from .ida import incremental_dynamic_analysis as _incremental_dynamic_analysis
from .optimize import optimal_damper as _optimal_damper
from .overturning_map import COARSE
from .overturning_map import overturning_map as _overturning_map
from .spectrum import SCAN_COARSE, TOL
from .spectrum import minimum_overturning_spectrum as _minimum_overturning_spectrum
from .suite import Suite
from .threshold import A_MAX
from .threshold import threshold_map as _threshold_map
from .tiles import Execution

#: Where the tiles of a study called from Python are kept, unless ``runs`` says otherwise.
RUNS = "out/runs"


def _setting(block, rtol: float, t_after: float, backend: str, pulse: str = "sine") -> Setting:
    return Setting(check_block(block), rtol=rtol, t_after=t_after, backend=backend, pulse=pulse)


def _tuning(damper) -> Tuning | Variant:
    """A study's damper from None (the default Tuning), a Tuning, a Variant, or a mapping of Tuning's keywords."""
    if damper is None:
        return Tuning()
    if isinstance(damper, Tuning | Variant):
        return damper
    if isinstance(damper, Mapping):
        try:
            return Tuning(**damper)
        except TypeError as exc:
            raise ParameterError(
                f"damper: {exc} (keywords of rocking.Tuning: gamma, omega_ratio, zeta, h, stops)"
            ) from None
    raise ParameterError(
        f"damper must be a rocking.Tuning, a rocking.Variant or a mapping such as {{'gamma': 0.05}} "
        f"(got {type(damper).__name__})"
    )


def _grid(name: str, values) -> Grid | None:
    if values is None or isinstance(values, Grid):
        return values
    return Grid.of(name, values)


def _suite(motions, unit: str | None) -> Suite:
    """A suite from a Suite, record files (paths) or pulses (:mod:`rocking.model.motion`)."""
    if isinstance(motions, Suite):
        return motions
    if isinstance(motions, str | os.PathLike):
        motions = [motions]
    try:
        items = list(motions)
    except TypeError:
        raise ParameterError(
            f"motions must be a rocking.Suite, record files or pulses (got {type(motions).__name__})"
        ) from None
    if items and all(isinstance(m, str | os.PathLike) for m in items):
        return Suite.from_files(items, unit)
    if unit is not None:
        raise ParameterError("unit is the unit of record files: give it with paths of records, not with pulses")
    return Suite.from_pulses(items)


def _run(study_function, *args, workers, progress: bool, runs, study: bool, **keywords):
    """``study_function(*args, execution, runs=runs, **keywords)``; its Study if ``study``, else its Dataset."""
    result = study_function(*args, Execution(workers=workers, progress=progress), runs=runs, **keywords)
    return result if study else result.to_dataset()


def overturning_map(
    block: Block,
    damper=None,
    *,
    Omega,
    beta,
    directions: str = "auto",
    full: bool = False,
    coarse: int = COARSE,
    verify: int | None = None,
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
):
    """The overturning map of ``block`` alone and with ``damper`` over ``Omega x beta``.

    Parameters
    ----------
    block : Block
    damper : Tuning, Variant or mapping, optional
        Default ``Tuning()`` (gamma 0.05, omega_ratio 1, zeta 0.05, h 0.05 m).
    Omega, beta : array_like or Grid
        Pulse frequency ratios ``omega_g / p`` and amplitude ratios ``a_g / (g tan alpha)``, increasing.
    directions, full, coarse, verify
        As :func:`rocking.study.overturning_map.overturning_map`.
    rtol, t_after, pulse, backend, workers, runs, progress, study
        Shared by every study (:mod:`rocking.study.api`).

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
        _setting(block, rtol, t_after, backend, pulse),
        _tuning(damper),
        _grid("Omega", Omega),
        _grid("beta", beta),
        workers=workers,
        progress=progress,
        runs=runs,
        study=study,
        directions=directions,
        full=full,
        coarse=coarse,
        verify=verify,
    )


def minimum_overturning_spectrum(
    block: Block,
    damper=None,
    *,
    Omega,
    beta,
    tol: float = TOL,
    coarse: int = SCAN_COARSE,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
):
    """The minimum overturning amplitude ``beta_min(Omega)`` of ``block`` alone and with ``damper``.

    ``beta`` are the scan amplitudes (their step bounds the safe windows seen); ``tol`` the relative
    tolerance of the bisection; ``coarse`` > 1: adaptive scans of that coarse step, which can miss bands
    narrower than it (:mod:`rocking.study.spectrum`; default every amplitude). Other parameters as
    :func:`overturning_map`.

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
        _setting(block, rtol, t_after, backend, pulse),
        _tuning(damper),
        _grid("Omega", Omega),
        _grid("beta", beta),
        workers=workers,
        progress=progress,
        runs=runs,
        study=study,
        tol=tol,
        coarse=coarse,
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
    tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
):
    """The damper period that most raises ``beta_min``, for each mass ratio of ``gammas``, against ``Omega``.

    ``Tm_ratio``: the coarse damper periods ``T_m p / (2 pi)`` searched, values > 0 or a logarithmic :class:`Grid`
    (default that of :func:`rocking.study.optimize.optimal_damper`). Other parameters as
    :func:`minimum_overturning_spectrum`.

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
        _setting(block, rtol, t_after, backend, pulse),
        gammas,
        _grid("Omega", Omega),
        _grid("beta", beta),
        workers=workers,
        progress=progress,
        runs=runs,
        study=study,
        zeta=zeta,
        h=h,
        stops=stops,
        Tm=_grid("Tm_ratio", Tm_ratio),
        tol=tol,
        directions=directions,
    )


def design(
    block: Block,
    *,
    Omega,
    beta,
    gamma: float = Tuning.gamma,
    stroke: float | None = None,
    h: float = Tuning.h,
    Tm_ratio=None,
    zeta=None,
    refine: int = REFINE,
    tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    pulse: str = "sine",
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
):
    """The damper with stops, of mass ``gamma M`` and half-stroke ``stroke`` (m), that most raises the worst
    ``beta_min`` over the band ``Omega`` in both directions.

    ``Tm_ratio`` and ``zeta``: the coarse damper periods ``T_m p / (2 pi)`` and damping ratios searched
    (arrays of values > 0 or log :class:`Grid`; defaults those of :func:`rocking.study.design.design`),
    ``refine`` points each side of the best. Other parameters as :func:`minimum_overturning_spectrum`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``Omega``, ``sign``, ``candidate``, ...; the damper in SI units in the attribute
        ``summary`` (JSON) and in the variables ``gain_opt``, ``stroke_use``, ``bumper_force_max`` (N).

    Examples
    --------
    >>> import json, tempfile, numpy as np, rocking
    >>> ds = rocking.design(rocking.Block.reference(), Omega=[4.0, 6.0], beta=np.linspace(0.5, 20.0, 27),
    ...                     Tm_ratio=np.geomspace(0.5, 4.0, 3), zeta=[0.02, 0.2], refine=1, runs=tempfile.mkdtemp(),
    ...                     progress=False)
    >>> damper = json.loads(ds.attrs["summary"])["damper"]
    >>> round(damper["m_kg"]), round(damper["k_m_N_per_m"], 1)  # kg, N/m
    (50, 178.4)
    """
    return _run(
        _design,
        _setting(block, rtol, t_after, backend, pulse),
        _grid("Omega", Omega),
        _grid("beta", beta),
        workers=workers,
        progress=progress,
        runs=runs,
        study=study,
        gamma=gamma,
        stroke=stroke,
        h=h,
        Tm=_grid("Tm_ratio", Tm_ratio),
        zeta=_grid("zeta", zeta),
        refine=refine,
        tol=tol,
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
    tol: float = TOL,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
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
    tol, directions, rtol, t_after, backend, workers, runs, progress, study
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
        tol=tol,
        rtol=rtol,
        t_after=t_after,
        backend=backend,
        directions=directions,
    )


def incremental_dynamic_analysis(
    block: Block,
    damper=None,
    *,
    motions,
    levels,
    measure: str = "scale",
    unit: str | None = None,
    directions: str = "auto",
    rtol: float = Setting.rtol,
    t_after: float = Setting.t_after,
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
    check: str | None = None,
):
    """Every motion of ``motions`` at every level of ``levels``, with and without ``damper``; the lognormal
    fragility fitted to the outcomes.

    Parameters
    ----------
    motions : Suite, paths of records, or pulses
        Record files (PEER ``.AT2``, two-column text, ...; ``unit`` as :meth:`rocking.study.suite.Suite.from_files`),
        pulses (:class:`rocking.OneSinePulse`, :class:`rocking.RickerWavelet`, ...) or a :class:`rocking.Suite`
        (e.g. :meth:`~rocking.study.suite.Suite.stochastic`).
    levels : array_like or Grid
        Scale factors (``measure="scale"``), or levels of the intensity measure in its SI unit: ``"pga"``
        (m/s^2), ``"pgv"`` (m/s), ``"arias"`` (m/s), ``"cav"`` (m/s), ``"amplitude"`` (m/s^2, pulses only).
    measure : {"scale", "pga", "pgv", "arias", "cav", "amplitude"}
        ``"scale"`` gives an IDA study, any other a fragility study.
    damper, directions, rtol, t_after, backend, workers, runs, progress, study
        As :func:`overturning_map`.
    check : {"tolerance", "none"}, optional
        The tolerance check of every response, as :func:`rocking.simulate`'s (docs/simulation.md,
        "Sensitivity to the tolerance"): by default ``"tolerance"`` for records and stochastic motions,
        ``"none"`` for pulses.

    Returns
    -------
    xarray.Dataset
        Dimensions ``part`` (``bare``, ``damper``), ``motion``, ``level``, ``sign``; the fitted curves at
        ``curve_x``; the envelope over the directions: :func:`rocking.study.ida.envelope`.

    Examples
    --------
    >>> import tempfile, rocking
    >>> block = rocking.Block.reference()
    >>> pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.5, 1.0, 2.0)]  # a_g 3 m/s^2, T_g in s
    >>> ds = rocking.incremental_dynamic_analysis(block, {"gamma": 0.05}, motions=pulses, levels=[1.0, 2.0, 4.0],
    ...                                           measure="amplitude", runs=tempfile.mkdtemp(), progress=False)
    >>> ds["fraction"].dims, ds["level"].attrs["units"]
    (('part', 'level'), 'm/s^2')
    """
    return _run(
        _incremental_dynamic_analysis,
        _setting(block, rtol, t_after, backend),
        _tuning(damper),
        _suite(motions, unit),
        _grid("levels", levels),
        workers=workers,
        progress=progress,
        runs=runs,
        study=study,
        measure_name=measure,
        directions=directions,
        check=check,
    )
