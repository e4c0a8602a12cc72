"""The studies with plain arguments, returning labelled data: ``rocking.overturning_map`` and its kin.

Each function takes a :class:`~rocking.model.params.Block`, the damper as a
:class:`~rocking.study.config.Tuning` or a mapping of its keywords (``gamma``, ``omega_ratio``,
``zeta``, ``h``, ``stops``), the swept quantities as arrays of values, and the solver and
execution options as keywords; it runs the study of :mod:`rocking.study` (tiles kept under
``runs``: a rerun loads them) and returns its :class:`xarray.Dataset`
(:mod:`rocking.study.dataset`). ``study=True`` returns the :class:`~rocking.study.config.Study`
instead, for :func:`rocking.save` and the figures.

"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from ..model.params import Block, ParameterError, check_block
from .config import Grid, Setting, Tuning, Variant
from .optimize import optimal_damper as _optimal_damper
from .overturning_map import COARSE
from .overturning_map import overturning_map as _overturning_map
from .spectrum import TOL
from .spectrum import minimum_overturning_spectrum as _minimum_overturning_spectrum
from .tiles import Execution

#: Where the tiles of a study called from Python are kept, unless ``runs`` says otherwise.
RUNS = "out/runs"


def _setting(block, rtol: float, t_after: float, backend: str, pulse: str) -> Setting:
    return Setting(check_block(block), rtol=rtol, t_after=t_after, backend=backend, pulse=pulse)


def _tuning(damper) -> Tuning | Variant:
    """A study's damper from a Tuning, a Variant, or a mapping of Tuning's keywords."""
    if isinstance(damper, Tuning | Variant):
        return damper
    if isinstance(damper, Mapping):
        try:
            return Tuning(**damper)
        except TypeError as exc:
            raise ParameterError(f"damper: {exc} (keywords of rocking.Tuning: gamma, omega_ratio, zeta, h, "
                                 f"stops)") from None  # fmt: skip
    raise ParameterError(
        f"damper must be a rocking.Tuning, a rocking.Variant or a mapping such as {{'gamma': 0.05}} "
        f"(got {type(damper).__name__})"
    )


def _grid(name: str, values) -> Grid:
    return values if isinstance(values, Grid) else Grid.of(name, values)


def _finish(result, study: bool):
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
    rtol: float = 1e-8,
    t_after: float = 15.0,
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
    directions, full, coarse
        As :func:`rocking.study.overturning_map.overturning_map`.
    rtol, t_after, pulse, backend
        The solver and the pulse family (:class:`~rocking.study.config.Setting`).
    workers, progress
        Local workers (default: all cores) and a progress bar (:class:`~rocking.study.tiles.Execution`).
    runs : path, optional
        Folder of the finished tiles (default ``out/runs``, as the command line's).
    study : bool, optional
        Return the :class:`Study`, not its ``Dataset``.

    Returns
    -------
    xarray.Dataset
        Dimensions ``Omega``, ``beta``, ``sign``; see :mod:`rocking.study.dataset`.

    Examples
    --------
    >>> import tempfile, numpy as np, rocking
    >>> ds = rocking.overturning_map(rocking.Block.reference(), {"gamma": 0.05}, Omega=[2.0, 4.0, 6.0],
    ...                              beta=np.linspace(1, 6, 4), runs=tempfile.mkdtemp(), progress=False)
    >>> ds["damper_overturned"].dims, ds["a_g"].attrs["units"]
    (('Omega', 'beta'), 'm/s^2')
    >>> int(ds["effect"].sum())  # cells saved by the damper minus cells lost
    0
    """
    result = _overturning_map(
        _setting(block, rtol, t_after, backend, pulse),
        _tuning(Tuning() if damper is None else damper),
        _grid("Omega", Omega),
        _grid("beta", beta),
        Execution(workers=workers, progress=progress),
        runs=runs,
        directions=directions,
        full=full,
        coarse=coarse,
    )
    return _finish(result, study)


def minimum_overturning_spectrum(
    block: Block,
    damper=None,
    *,
    Omega,
    beta,
    tol: float = TOL,
    directions: str = "auto",
    rtol: float = 1e-8,
    t_after: float = 15.0,
    pulse: str = "sine",
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
):
    """The minimum overturning amplitude ``beta_min(Omega)`` of ``block`` alone and with ``damper``.

    ``beta`` are the scan amplitudes (their step bounds the safe windows seen); ``tol`` the relative
    tolerance of the bisection. Other parameters as :func:`overturning_map`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``Omega``, ``sign``, ``beta_scan``; ``<part>_flag`` says which ``beta_min`` are bounds.

    Examples
    --------
    >>> import tempfile, rocking
    >>> ds = rocking.minimum_overturning_spectrum(rocking.Block.reference(), None, Omega=[2.0, 6.0],
    ...                                           beta=[0.5, 2, 4, 8, 15], runs=tempfile.mkdtemp(), progress=False)
    >>> ds["bare_beta_min"].round(2).values.tolist(), ds["bare_flag"].attrs["flag_meanings"]
    ([1.15, 2.82], 'upper_bound bracketed lower_bound')
    """
    result = _minimum_overturning_spectrum(
        _setting(block, rtol, t_after, backend, pulse),
        _tuning(Tuning() if damper is None else damper),
        _grid("Omega", Omega),
        _grid("beta", beta),
        Execution(workers=workers, progress=progress),
        tol=tol,
        runs=runs,
        directions=directions,
    )
    return _finish(result, study)


def optimal_damper(
    block: Block,
    gammas,
    *,
    Omega,
    beta,
    zeta: float = 0.05,
    h: float = 0.05,
    stops: bool = False,
    Tm_ratio=None,
    tol: float = TOL,
    directions: str = "auto",
    rtol: float = 1e-8,
    t_after: float = 15.0,
    pulse: str = "sine",
    backend: str = "c",
    workers: int | None = None,
    runs: str | Path = RUNS,
    progress: bool = True,
    study: bool = False,
):
    """The damper period that most raises ``beta_min``, for each mass ratio of ``gammas``, against ``Omega``.

    ``Tm_ratio``: the coarse damper periods ``T_m p / (2 pi)`` searched, a logarithmic :class:`Grid`
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
    result = _optimal_damper(
        _setting(block, rtol, t_after, backend, pulse),
        gammas,
        _grid("Omega", Omega),
        _grid("beta", beta),
        Execution(workers=workers, progress=progress),
        zeta=zeta,
        h=h,
        stops=stops,
        Tm=Tm_ratio,
        tol=tol,
        runs=runs,
        directions=directions,
    )
    return _finish(result, study)
