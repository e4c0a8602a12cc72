"""The C back end: ``rocking/csrc/sim.c`` through ctypes.

:func:`simulate` runs one :class:`~rocking.sim.problem.Problem` and
:func:`simulate_batch` many runs of one model given as arrays; both follow the
phase machine of ``docs/simulation.md``, like :mod:`rocking.sim.numpy_backend`,
with a hand-written Dormand-Prince 5(4) in C. The library of a model is built
at first use by :mod:`rocking.sim.cbuild` (cached on disk) and loaded once per
process.

ctypes releases the GIL during a foreign call, so :func:`simulate_batch` runs
its chunks on threads in parallel.
"""

from __future__ import annotations

import ctypes
import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from . import cbuild
from .cbuild import CBuildError
from ..model.loading import Model, load_model
from .problem import RESULT_FIELDS, STATUS, Problem, Response

__all__ = ["CBuildError", "SimulationError", "available", "batch_arguments", "library", "simulate", "simulate_batch"]

_API_VERSION = 2  # ROCKING_SIM_API_VERSION of sim.h
_FAILED = -1  # ROCKING_FAILED

_dbl = ctypes.c_double
_dbl_p = ctypes.POINTER(ctypes.c_double)
_i32_p = ctypes.POINTER(ctypes.c_int32)


class SimulationError(RuntimeError):
    """The C integrator failed (its step size underflowed, e.g. on a non-finite right-hand side)."""


class _Case(ctypes.Structure):
    """``rocking_case`` of sim.h."""

    _fields_ = [
        ("a_g", _dbl),
        ("omega_g", _dbl),
        ("psi", _dbl),
        ("t_p", _dbl),
        ("t_max", _dbl),
        ("rtol", _dbl),
        ("atol", _dbl_p),
        ("contact_max_step", _dbl),
        ("dtheta_rest", _dbl),
        ("energy_rest", _dbl),
        ("max_events", ctypes.c_int64),
        ("record_dt", _dbl),
        ("y0", _dbl_p),
        ("phase0", ctypes.c_int32),
        ("early_rest", ctypes.c_int32),
    ]


class _Result(ctypes.Structure):
    """``rocking_result`` of sim.h (one run; a batch uses :data:`RESULT_DTYPE`)."""

    _fields_ = [
        ("status", ctypes.c_int32),
        ("overturned", ctypes.c_int32),
        ("impacts", ctypes.c_int64),
        ("uplifts", ctypes.c_int64),
        ("t_overturn", _dbl),
        ("t_critical", _dbl),
        ("theta_max", _dbl),
        ("x_max", _dbl),
        ("t_end", _dbl),
    ]


class _History(ctypes.Structure):
    """``rocking_history`` of sim.h."""

    _fields_ = [("capacity", ctypes.c_int64), ("t", _dbl_p), ("y", _dbl_p), ("phase", _i32_p), ("ag", _dbl_p)]


#: ``rocking_result`` of sim.h as a NumPy record (64 bytes, no padding).
RESULT_DTYPE = np.dtype(
    [
        ("status", np.int32),
        ("overturned", np.int32),
        ("impacts", np.int64),
        ("uplifts", np.int64),
        ("t_overturn", np.float64),
        ("t_critical", np.float64),
        ("theta_max", np.float64),
        ("x_max", np.float64),
        ("t_end", np.float64),
    ],
    align=True,
)

assert ctypes.sizeof(_Result) == RESULT_DTYPE.itemsize == 64


def _array_arg(dtype, ndim: int):
    return np.ctypeslib.ndpointer(dtype=dtype, ndim=ndim, flags="C_CONTIGUOUS")


class _Library:
    """The compiled ``sim.c`` of one model, with typed entry points."""

    def __init__(self, model: Model, path: Path):
        self.model = model
        self.path = path
        self.ny = len(model.state)
        self.np = len(model.parameters)
        lib = ctypes.CDLL(str(path))
        for name in (
            "rocking_model_nq",
            "rocking_model_ny",
            "rocking_model_np",
            "rocking_result_size",
            "rocking_api_version",
        ):
            getattr(lib, name).restype = ctypes.c_int
            getattr(lib, name).argtypes = []
        found = (
            lib.rocking_api_version(),
            lib.rocking_model_nq(),
            lib.rocking_model_ny(),
            lib.rocking_model_np(),
            lib.rocking_result_size(),
        )
        wanted = (_API_VERSION, model.nq, self.ny, self.np, RESULT_DTYPE.itemsize)
        if found != wanted:
            raise CBuildError(
                f"{path}: (api, nq, ny, np, sizeof result) = {found}, expected {wanted} for model {model.name!r}"
            )
        lib.rocking_simulate.restype = ctypes.c_int64
        # One run: plain pointers (the arrays are checked in Python, cheaply).
        lib.rocking_simulate.argtypes = [
            _dbl_p,
            ctypes.POINTER(_Case),
            ctypes.POINTER(_Result),
            ctypes.POINTER(_History),
        ]
        # A batch: NumPy checks dtype, dimensions and contiguity of every array.
        vector, matrix = _array_arg(np.float64, 1), _array_arg(np.float64, 2)
        lib.rocking_simulate_batch.restype = None
        lib.rocking_simulate_batch.argtypes = (
            [ctypes.c_int64, matrix]  # n, p
            + [vector] * 5  # a_g, omega_g, psi, t_p, t_max
            + [matrix]  # atol
            + [vector] * 3  # contact_max_step, dtheta_rest, energy_rest
            + [_dbl, ctypes.c_int64, ctypes.c_int32, _array_arg(RESULT_DTYPE, 1)]  # rtol, max_events, early_rest, out
        )
        self.lib = lib


_LIBRARIES: dict[tuple[Path, str], _Library] = {}
_LIBRARIES_LOCK = threading.Lock()


def library(model: str | Model = "omd") -> _Library:
    """The loaded C library of ``model``: built (or found in the disk cache) at first use, then kept.

    Raises
    ------
    CBuildError
        If the library cannot be built or does not match the model.
    """
    model = load_model(model)
    key = (model.folder, model.c_prefix)
    with _LIBRARIES_LOCK:
        lib = _LIBRARIES.get(key)
        if lib is None:
            path = cbuild.build(model)
            try:
                lib = _Library(model, path)
            except OSError as exc:
                raise CBuildError(f"cannot load {path}: {exc}") from None
            _LIBRARIES[key] = lib
        return lib


def available(model: str | Model = "omd") -> bool:
    """Whether the C back end can be built and loaded for ``model``."""
    try:
        library(model)
    except CBuildError:
        return False
    return True


# --------------------------------------------------------------------------- #
# One problem                                                                  #
# --------------------------------------------------------------------------- #


def _vector(name: str, value, size: int) -> np.ndarray:
    a = np.ascontiguousarray(value, dtype=np.float64).reshape(-1)
    if a.shape != (size,):
        raise ValueError(f"{name} must hold {size} values (got shape {np.shape(value)})")
    return a


#: The lower bound of each per-run setting: ">" it, ">=" it, or None (finite only).
_BOUNDS = {
    "a_g": None,
    "omega_g": None,
    "psi": None,
    "t_p": None,
    "t_max": None,
    "contact_max_step": ">",
    "dtheta_rest": ">=",
    "energy_rest": ">=",
}


def _setting_error(name: str, value: float) -> ValueError:
    bound = _BOUNDS[name]
    return ValueError(f"{name} must be {f'finite and {bound} 0' if bound else 'finite'} (got {float(value)!r})")


def _setting_ok(value: float, bound: str | None) -> bool:
    return math.isfinite(value) and (bound is None or (value > 0 if bound == ">" else value >= 0))


def _check_tolerances(atol: np.ndarray, rtol: float) -> None:
    if not (math.isfinite(rtol) and rtol > 0):
        raise ValueError(f"rtol must be a finite number > 0 (got {rtol})")
    if not np.all(np.isfinite(atol) & (atol >= 0)):
        raise ValueError("atol must be finite and >= 0")


def _check_batch_settings(values: dict[str, np.ndarray]) -> None:
    """Every per-run setting within its bounds: finite, and positive where the run needs it."""
    for name, bound in _BOUNDS.items():
        v = values[name]
        with np.errstate(invalid="ignore"):
            ok = np.isfinite(v) & ((v > 0) if bound == ">" else (v >= 0) if bound == ">=" else True)
        if not np.all(ok):
            raise _setting_error(name, v[~ok][0])


def _status(code: int, where: str) -> str:
    if code == _FAILED:
        raise SimulationError(f"the C integrator failed {where}: step size underflow (non-finite state?)")
    return STATUS[code]


def _history_capacity(problem: Problem) -> int:
    """First guess of a history's length: the samples plus room for a few hundred events.

    A longer history is not lost: the run is repeated with buffers of the size it reported.
    """
    samples = problem.t_max / problem.record_dt if problem.record_dt > 0 else 0.0
    return int(min(samples, 1 << 16)) + 512


def simulate(problem: Problem, record: bool = False, *, y0=None, phase0=None) -> Response:
    """Simulate one problem in C, following docs/simulation.md.

    Parameters
    ----------
    problem : Problem
        The run (see :func:`rocking.sim.problem.make_problem`).
    record : bool
        Keep the history: samples every ``problem.record_dt`` from the dense
        output plus every event (uplift, impact before and after, rest, pulse
        end, overturning, end), in time order.
    y0 : array_like, optional
        State at ``t = 0`` in manifest order; default at rest (all zeros).
    phase0 : int, optional
        Phase at ``t = 0``: 0 (full contact, needs ``theta = dtheta = 0``),
        ``+1`` or ``-1`` (rocking about that pivot, needs ``s theta >= 0``, and
        from ``theta = 0`` a ``dtheta`` towards ``s``). Default 0.

    Returns
    -------
    Response
        With ``history`` (``t``, each state component by name, ``phase``,
        ``ag``) when ``record`` is true.

    Raises
    ------
    CBuildError
        If the C back end cannot be built.
    ValueError
        If ``y0`` or ``phase0`` are invalid.
    SimulationError
        If the integrator fails.
    """
    lib = library(problem.model)
    p = _vector("p", problem.p, lib.np)
    atol = _vector("atol", problem.atol, lib.ny)
    _check_tolerances(atol, float(problem.rtol))
    for name, bound in _BOUNDS.items():
        # A zero step bound or an infinite t_max would never end.
        if not _setting_ok(float(getattr(problem, name)), bound):
            raise _setting_error(name, getattr(problem, name))
    y0 = None if y0 is None else _vector("y0", y0, lib.ny)
    case = _Case(
        a_g=problem.a_g,
        omega_g=problem.omega_g,
        psi=problem.psi,
        t_p=problem.t_p,
        t_max=problem.t_max,
        rtol=problem.rtol,
        atol=atol.ctypes.data_as(_dbl_p),
        contact_max_step=problem.contact_max_step,
        dtheta_rest=problem.dtheta_rest,
        energy_rest=problem.energy_rest,
        max_events=int(problem.max_events),
        record_dt=problem.record_dt,
        y0=None if y0 is None else y0.ctypes.data_as(_dbl_p),
        phase0=0 if phase0 is None else int(phase0),
        early_rest=int(bool(problem.early_rest)),
    )
    result = _Result()
    history = None
    capacity = _history_capacity(problem) if record else 0
    while True:
        buffers = None
        if record:
            buffers = {
                "t": np.empty(capacity),
                "y": np.empty((capacity, lib.ny)),
                "phase": np.empty(capacity, dtype=np.int32),
                "ag": np.empty(capacity),
            }
            history = _History(
                capacity,
                buffers["t"].ctypes.data_as(_dbl_p),
                buffers["y"].ctypes.data_as(_dbl_p),
                buffers["phase"].ctypes.data_as(_i32_p),
                buffers["ag"].ctypes.data_as(_dbl_p),
            )
        n = lib.lib.rocking_simulate(
            p.ctypes.data_as(_dbl_p),
            ctypes.byref(case),
            ctypes.byref(result),
            ctypes.byref(history) if record else None,
        )
        if n < 0:
            raise ValueError(
                f"invalid initial state: phase0 = {phase0!r} with y0 = {None if y0 is None else y0.tolist()} "
                f"({', '.join(problem.model.state)})"
            )
        if n <= capacity:
            break
        capacity = int(n)  # the run is deterministic: the same run again, with room for all of it
    status = _status(result.status, f"at t = {result.t_end:.17g}")
    hist = None
    if record:
        hist = {"t": buffers["t"][:n].copy()}
        for i, name in enumerate(problem.model.state):
            hist[name] = buffers["y"][:n, i].copy()
        hist["phase"] = buffers["phase"][:n].astype(int)
        hist["ag"] = buffers["ag"][:n].copy()
    return Response(
        overturned=bool(result.overturned),
        t_overturn=result.t_overturn,
        t_critical=result.t_critical,
        theta_max=result.theta_max,
        x_max=result.x_max,
        impacts=result.impacts,
        uplifts=result.uplifts,
        t_end=result.t_end,
        status=status,
        history=hist,
    )


# --------------------------------------------------------------------------- #
# Many runs of one model                                                       #
# --------------------------------------------------------------------------- #


def _default_threads() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def simulate_batch(
    model,
    p,
    a_g,
    omega_g,
    psi,
    t_p,
    t_max,
    atol,
    contact_max_step,
    dtheta_rest,
    energy_rest,
    *,
    rtol: float,
    max_events: int,
    early_rest: bool = True,
    threads: int | None = None,
) -> dict[str, np.ndarray]:
    """Simulate ``n`` runs of ``model`` from rest, without history.

    Parameters
    ----------
    model : str or Model
        The generated model.
    p : array_like, shape (n, np)
        Parameters in manifest order, one row per run (a single row broadcasts).
    a_g, omega_g, psi, t_p, t_max : array_like, shape (n,)
        Pulse and end of each run (scalars broadcast).
    atol : array_like, shape (n, ny)
        Absolute tolerances (a single row broadcasts).
    contact_max_step, dtheta_rest, energy_rest : array_like, shape (n,)
        As in :class:`~rocking.sim.problem.Problem` (scalars broadcast).
    rtol : float
        Relative tolerance, common to all runs.
    max_events : int
        Bound on uplifts plus impacts, common to all runs.
    early_rest : bool
        The early rest of :class:`~rocking.sim.problem.Problem`, common to all runs.
    threads : int, optional
        Threads to run chunks of the batch on (the GIL is released in C);
        default all the CPUs this process may use. The results do not depend
        on it.

    Returns
    -------
    dict of ndarray
        ``overturned`` (bool), ``t_overturn``, ``t_critical``, ``theta_max``,
        ``x_max``, ``impacts``, ``uplifts``, ``t_end``, ``status`` (int64
        indices into :data:`rocking.sim.problem.STATUS`), each of shape ``(n,)``.

    Raises
    ------
    CBuildError
        If the C back end cannot be built.
    ValueError
        If the arrays do not fit together or ``rtol`` / ``max_events`` are invalid.
    SimulationError
        If the integrator fails on any run (the message lists them).
    """
    lib = library(model)
    rtol = float(rtol)
    if int(max_events) != max_events or max_events < 1:
        raise ValueError(f"max_events must be an integer >= 1 (got {max_events!r})")
    p = np.asarray(p, dtype=np.float64)
    atol = np.asarray(atol, dtype=np.float64)
    if p.shape[-1:] != (lib.np,) or p.ndim > 2:
        raise ValueError(f"p must have shape (n, {lib.np}) for model {lib.model.name!r} (got {p.shape})")
    if atol.shape[-1:] != (lib.ny,) or atol.ndim > 2:
        raise ValueError(f"atol must have shape (n, {lib.ny}) for model {lib.model.name!r} (got {atol.shape})")
    vectors = {
        "a_g": a_g,
        "omega_g": omega_g,
        "psi": psi,
        "t_p": t_p,
        "t_max": t_max,
        "contact_max_step": contact_max_step,
        "dtheta_rest": dtheta_rest,
        "energy_rest": energy_rest,
    }
    vectors = {k: np.asarray(v, dtype=np.float64) for k, v in vectors.items()}
    shapes = [v.shape for v in vectors.values()] + [p.shape[:-1], atol.shape[:-1]]
    if any(len(s) > 1 for s in shapes):
        raise ValueError(f"per-run arguments must be 1-D (got shapes {shapes})")
    try:
        (n,) = np.broadcast_shapes(*shapes, (1,))
    except ValueError:
        raise ValueError(f"per-run arguments have different lengths (shapes {shapes})") from None
    vectors = {k: np.ascontiguousarray(np.broadcast_to(v, (n,))) for k, v in vectors.items()}
    p = np.ascontiguousarray(np.broadcast_to(p, (n, lib.np)))
    atol = np.ascontiguousarray(np.broadcast_to(atol, (n, lib.ny)))
    _check_tolerances(atol, rtol)
    _check_batch_settings(vectors)
    out = np.zeros(n, dtype=RESULT_DTYPE)
    args = [vectors[k] for k in ("a_g", "omega_g", "psi", "t_p", "t_max")]
    rest = [vectors[k] for k in ("contact_max_step", "dtheta_rest", "energy_rest")]

    def run(lo: int, hi: int) -> None:
        # Row slices of C-contiguous arrays are C-contiguous: no copies.
        lib.lib.rocking_simulate_batch(
            hi - lo,
            p[lo:hi],
            *(a[lo:hi] for a in args),
            atol[lo:hi],
            *(a[lo:hi] for a in rest),
            rtol,
            int(max_events),
            int(bool(early_rest)),
            out[lo:hi],
        )

    threads = _default_threads() if threads is None else int(threads)
    if threads < 1:
        raise ValueError(f"threads must be >= 1 (got {threads})")
    threads = min(threads, max(n, 1))
    if threads == 1:
        run(0, n)
    else:
        # More chunks than threads: runs differ a lot in cost (an early overturn
        # against a long rocking history), small chunks keep the threads busy.
        bounds = np.linspace(0, n, min(n, 8 * threads) + 1).astype(int)
        with ThreadPoolExecutor(max_workers=threads) as pool:
            for future in [pool.submit(run, lo, hi) for lo, hi in zip(bounds[:-1], bounds[1:]) if hi > lo]:
                future.result()
    failed = np.flatnonzero(out["status"] == _FAILED)
    if failed.size:
        raise SimulationError(
            f"the C integrator failed on {failed.size} of {n} runs (step size underflow), e.g. run(s) "
            f"{failed[:10].tolist()}"
        )
    return {name: out[name].astype(dtype) for name, dtype in RESULT_FIELDS.items()}


def batch_arguments(problems) -> dict:
    """The arguments of :func:`simulate_batch` for a list of problems of one model.

    ``simulate_batch(**batch_arguments(problems))`` gives the results of
    ``[simulate(pr) for pr in problems]`` as arrays (without histories).

    Raises
    ------
    ValueError
        If the list is empty, or the problems differ in model, ``rtol``, ``max_events`` or ``early_rest``.
    """
    problems = list(problems)
    if not problems:
        raise ValueError("no problems given")
    first = problems[0]
    for name in ("rtol", "max_events", "early_rest"):
        values = {getattr(pr, name) for pr in problems}
        if len(values) > 1:
            raise ValueError(f"a batch needs one {name} for all problems (got {sorted(values)})")
    folders = {pr.model.folder for pr in problems}
    if len(folders) > 1:
        raise ValueError(f"a batch needs one model for all problems (got {sorted(str(f) for f in folders)})")

    def column(name):
        return np.array([float(getattr(pr, name)) for pr in problems])

    return {
        "model": first.model,
        "p": np.array([np.asarray(pr.p, dtype=float) for pr in problems]),
        "a_g": column("a_g"),
        "omega_g": column("omega_g"),
        "psi": column("psi"),
        "t_p": column("t_p"),
        "t_max": column("t_max"),
        "atol": np.array([np.asarray(pr.atol, dtype=float) for pr in problems]),
        "contact_max_step": column("contact_max_step"),
        "dtheta_rest": column("dtheta_rest"),
        "energy_rest": column("energy_rest"),
        "rtol": float(first.rtol),
        "max_events": int(first.max_events),
        "early_rest": bool(first.early_rest),
    }
