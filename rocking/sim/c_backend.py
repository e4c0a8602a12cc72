"""The C back end: ``rocking/sim/csrc/sim.c`` through ctypes.

:func:`simulate` runs one :class:`~rocking.sim.problem.Problem` and
:func:`simulate_cases` the runs of a :class:`~rocking.sim.batch.Cases`; both
follow the phase machine of ``docs/simulation.md``, like
:mod:`rocking.sim.numpy_backend`, with a hand-written Dormand-Prince 5(4) in
C. The structures that cross the boundary are built from the tables of
:mod:`rocking.sim.boundary`, and a library whose layout or constants differ
from them is refused at load. The library of a model is built at first use by
:mod:`rocking.sim.cbuild` (cached on disk) and loaded once per process.

ctypes releases the GIL during a foreign call, so :func:`simulate_cases` runs
its chunks on threads in parallel.

Every call passes sim.c a stop flag of its own (``rocking_control.stop``),
which the runs read once per step: :func:`request_stop` sets the flags of all
the calls running in this process, which then raise :exc:`KeyboardInterrupt`
within a few milliseconds; calls started later run normally. Called from the
main thread, a C handler of SIGINT sets the flag while C runs, so that Ctrl-C
stops them too (:func:`_stoppable`).
"""

from __future__ import annotations

import ctypes
import math
import os
import signal
import threading
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..model.loading import Model, load_model
from . import boundary, cbuild
from .batch import Cases
from .boundary import CASE, DOUBLES, RESULT, SERIES
from .cbuild import CBuildError
from .history import FLIGHT_COLUMNS, FLOOR_COLUMNS
from .problem import RESULT_FIELDS, Problem, Response, SimulationError

__all__ = [
    "CBuildError",
    "SimulationError",
    "available",
    "library",
    "request_stop",
    "simulate",
    "simulate_cases",
    "simulate_settings",
]

_dbl = ctypes.c_double
_dbl_p = ctypes.POINTER(ctypes.c_double)
_i32_p = ctypes.POINTER(ctypes.c_int32)
_i64_p = ctypes.POINTER(ctypes.c_int64)

#: ctypes and NumPy types of each kind of field of the boundary tables.
_CTYPES = {boundary.DOUBLE: _dbl, boundary.INT64: ctypes.c_int64, boundary.INT32: ctypes.c_int32}
# An address, as in a batch's records (CASE_DTYPE): set from ``ndarray.ctypes.data`` without a ctypes cast.
_CTYPES.update({DOUBLES: ctypes.c_void_p, SERIES: ctypes.c_void_p})
_NUMPY = {boundary.DOUBLE: np.float64, boundary.INT64: np.int64, boundary.INT32: np.int32}
_NUMPY.update({DOUBLES: np.uintp, SERIES: np.uintp})


def _structure(name: str, fields) -> type[ctypes.Structure]:
    return type(name, (ctypes.Structure,), {"_fields_": [(f.name, _CTYPES[f.kind]) for f in fields]})


def _record(fields) -> np.dtype:
    return np.dtype([(f.name, _NUMPY[f.kind]) for f in fields], align=True)


_Case = _structure("_Case", CASE)
_Result = _structure("_Result", RESULT)
#: ``rocking_case`` and ``rocking_result`` as NumPy records, for a batch.
CASE_DTYPE, RESULT_DTYPE = _record(CASE), _record(RESULT)


class _History(ctypes.Structure):
    """``rocking_history`` of sim.h."""

    _fields_ = [
        ("capacity", ctypes.c_int64),
        ("t", _dbl_p),
        ("y", _dbl_p),
        ("phase", _i32_p),
        ("ag", _dbl_p),
        ("floor", _dbl_p),
        ("slide", _i32_p),
        ("flight", _dbl_p),
    ]


#: sim.h's ``rocking_history.floor``, in its order: the floor's columns of a history but the slip's sign, which
#: has its own buffer (``slide``).
FLOOR_BUFFER = FLOOR_COLUMNS[:-1]


class _Control(ctypes.Structure):
    """``rocking_control`` of sim.h: the stop flag of one call and the model's impact laws."""

    _fields_ = [("stop", _i32_p), ("velocity_law", _i32_p)]


def _layout(structure, dtype: np.dtype, fields) -> list[int]:
    """Offsets of ``fields`` then the size, as ctypes lays ``structure`` out; the NumPy record must agree."""
    offsets = [getattr(structure, f.name).offset for f in fields] + [ctypes.sizeof(structure)]
    record = dtype.fields  # None only for a dtype that is no record
    assert record is not None and offsets == [record[f.name][1] for f in fields] + [dtype.itemsize]
    return offsets


def _check_library(lib, model: Model, path: Path) -> None:
    """Refuse a library whose sizes, layout or constants differ from the boundary tables and ``model``."""
    found = (lib.rocking_api_version(), lib.rocking_model_nq(), lib.rocking_model_ny(), lib.rocking_model_np())
    wanted = (boundary.API_VERSION, model.nq, len(model.state), len(model.parameters))
    if found != wanted:
        raise CBuildError(f"{path}: (api, nq, ny, np) = {found}, expected {wanted} for model {model.name!r}")
    case = np.zeros(len(CASE) + 1, dtype=np.int64)
    result = np.zeros(len(RESULT) + 1, dtype=np.int64)
    lib.rocking_layout(case.ctypes.data_as(_i64_p), result.ctypes.data_as(_i64_p))
    for name, c_side, py_side in (
        ("rocking_case", case, _layout(_Case, CASE_DTYPE, CASE)),
        ("rocking_result", result, _layout(_Result, RESULT_DTYPE, RESULT)),
    ):
        if c_side.tolist() != py_side:
            raise CBuildError(f"{path}: {name} offsets and size {c_side.tolist()} differ from the table's {py_side}")
    values = boundary.constant_values()
    constants = np.zeros(len(values))
    lib.rocking_constants(constants.ctypes.data_as(_dbl_p))
    if tuple(constants) != values:
        raise CBuildError(f"{path}: constants {tuple(constants)} differ from rocking.sim.boundary's {values}")


def _array_arg(dtype, ndim: int):
    return np.ctypeslib.ndpointer(dtype=dtype, ndim=ndim, flags="C_CONTIGUOUS")


class _Library:
    """The compiled ``sim.c`` of one model, with typed entry points, checked against the boundary tables."""

    def __init__(self, model: Model, path: Path):
        self.model = model
        self.path = path
        self.ny = len(model.state)
        self.np = len(model.parameters)
        lib = ctypes.CDLL(str(path))
        for name in ("rocking_model_nq", "rocking_model_ny", "rocking_model_np", "rocking_api_version"):
            getattr(lib, name).restype = ctypes.c_int
            getattr(lib, name).argtypes = []
        lib.rocking_layout.restype = None
        lib.rocking_layout.argtypes = [_i64_p, _i64_p]
        lib.rocking_constants.restype = None
        lib.rocking_constants.argtypes = [_dbl_p]
        _check_library(lib, model, path)
        lib.rocking_simulate.restype = ctypes.c_int64
        # The parameters by address, as the arrays of a case: an int, not a ctypes pointer built per call.
        lib.rocking_simulate.argtypes = [
            ctypes.c_void_p,
            ctypes.POINTER(_Case),
            ctypes.POINTER(_Result),
            ctypes.POINTER(_History),
            ctypes.POINTER(_Control),
        ]
        lib.rocking_sigint_catch.restype = ctypes.c_int
        lib.rocking_sigint_catch.argtypes = [ctypes.POINTER(ctypes.c_int32)]
        lib.rocking_sigint_release.restype = ctypes.c_int
        lib.rocking_sigint_release.argtypes = []
        batch = [
            ctypes.c_int64,
            _array_arg(np.float64, 2),
            _array_arg(CASE_DTYPE, 1),
            _array_arg(RESULT_DTYPE, 1),
            ctypes.POINTER(_Control),
        ]
        lib.rocking_simulate_batch.restype = None
        lib.rocking_simulate_batch.argtypes = batch
        lib.rocking_simulate_batch_lanes.restype = None
        lib.rocking_simulate_batch_lanes.argtypes = [*batch, ctypes.c_int32]
        lib.rocking_lanes.restype = ctypes.c_int
        lib.rocking_lanes.argtypes = []
        self.lib = lib
        # The impact law of each coordinate (the model header does not carry them): 1 for "velocity".
        laws = model.manifest.get("options", {}).get("impact_laws", {})
        self.velocity_law = (ctypes.c_int32 * model.nq)(
            *[int(laws.get(name) == "velocity") for name in model.coordinates]
        )
        self._velocity_law = ctypes.cast(self.velocity_law, _i32_p)  # cast once: a cast costs microseconds

    def control(self, stop: ctypes.c_int32) -> _Control:
        """The ``rocking_control`` of one call with the stop flag ``stop``."""
        return _Control(ctypes.pointer(stop), self._velocity_law)


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
# Stopping                                                                     #
# --------------------------------------------------------------------------- #

#: The stop flags of the calls running now (sim.c reads each once per step).
_RUNNING: dict[int, ctypes.c_int32] = {}
_RUNNING_LOCK = threading.Lock()
#: Set inside :func:`halted`: calls that start are stopped at once too.
_HALTED = threading.Event()


def request_stop() -> None:
    """Stop every C run and batch running now in this process.

    Each of their :func:`simulate` / :func:`simulate_cases` calls raises
    :exc:`KeyboardInterrupt` within a few milliseconds (a run reads its flag
    once per step of the integrator); calls started afterwards run normally.
    Safe to call from any thread, or from a signal handler.
    """
    with _RUNNING_LOCK:
        flags = list(_RUNNING.values())
    for flag in flags:
        flag.value = 1


@contextmanager
def halted() -> Iterator[None]:
    """Stop every C run of this process, and every one that starts inside the ``with``.

    :func:`request_stop` spares the calls that start after it; a study's
    interruption needs them stopped too: between the stop and the end of its
    pool, a worker thread may still take a queued tile and start its C call.
    """
    with _RUNNING_LOCK:
        _HALTED.set()
    request_stop()
    try:
        yield
    finally:
        _HALTED.clear()


def _stoppable(call, lib):
    """``call(stop)`` with a fresh stop flag registered for :func:`request_stop`.

    From the main thread, a C handler of SIGINT (``rocking_sigint_catch`` of ``lib``) sets the flag
    while C runs, since Python runs its own handler only between bytecodes; Python's handler is
    put back afterwards and the signal raised again, so Ctrl-C stops the runs and raises
    :exc:`KeyboardInterrupt` (or does what the program's own handler does) at once.
    """
    stop = ctypes.c_int32(0)
    with _RUNNING_LOCK:
        _RUNNING[id(stop)] = stop
        stop.value = int(_HALTED.is_set())
    try:
        if threading.current_thread() is not threading.main_thread():
            return call(stop)
        catching = lib.rocking_sigint_catch(ctypes.byref(stop))
        try:
            result = call(stop)
        finally:
            caught = catching and lib.rocking_sigint_release()
        if caught:
            request_stop()
            signal.raise_signal(signal.SIGINT)
        return result
    finally:
        with _RUNNING_LOCK:
            del _RUNNING[id(stop)]


# --------------------------------------------------------------------------- #
# One problem                                                                  #
# --------------------------------------------------------------------------- #


#: The fields of ``rocking_case`` in order, and the positions of the arrays among them (passed by their address).
_CASE_NAMES = tuple(f.name for f in CASE)
_CASE_ARRAYS = tuple(i for i, f in enumerate(CASE) if f.kind in (DOUBLES, SERIES))


def _address(values, keep: list) -> int | None:
    """The address of ``values`` as C doubles (``None``: NULL); a copy it needs is appended to ``keep``.

    An array's own values when they are C-contiguous doubles (``__array_interface__`` is cheaper than
    ``ndarray.ctypes``), else a copy; a list's or tuple's in a C array.
    """
    if values is None:
        return None
    if isinstance(values, (list, tuple)):
        keep.append((ctypes.c_double * len(values))(*values))
        return ctypes.addressof(keep[-1])
    array = np.ascontiguousarray(values, dtype=np.float64)
    keep.append(array)
    return array.__array_interface__["data"][0]


def _case(settings: dict, keep: list) -> ctypes.Structure:
    """``settings`` (every field of :data:`~rocking.sim.boundary.CASE` by name) as a ``rocking_case``.

    Its arrays stay owned by ``settings`` or by ``keep``, which the caller holds during the run.
    """
    values = [settings[name] for name in _CASE_NAMES]
    for i in _CASE_ARRAYS:
        values[i] = _address(values[i], keep)
    return _Case(*values)


def _failed(where: str) -> SimulationError:
    return SimulationError(f"the C integrator failed {where}: step size underflow (non-finite state?)")


def _history_capacity(settings: dict) -> int:
    """First guess of a history's length: the samples plus room for a few hundred events.

    A longer history is not lost: the run is repeated with buffers of the size it reported.
    """
    t_max, record_dt = settings["t_max"], settings["record_dt"]
    samples = t_max / record_dt if record_dt > 0 else 0.0
    return int(min(samples, 1 << 16)) + 512


def simulate(problem: Problem, record: bool = False) -> Response:
    """Simulate one problem in C, following docs/simulation.md.

    Parameters
    ----------
    problem : Problem
        The run (see :func:`rocking.sim.problem.make_problem`), its initial
        state included.
    record : bool
        Keep the history: samples every ``problem.record_dt`` from the dense
        output plus every event (uplift, impact before and after, rest, pulse
        end, overturning, end), in time order.

    Returns
    -------
    Response
        With ``history`` (``t``, each state component by name, ``phase``,
        ``ag``) when ``record`` is true.

    Raises
    ------
    CBuildError
        If the C back end cannot be built.
    SimulationError
        If the integrator fails.
    KeyboardInterrupt
        If :func:`request_stop` (or Ctrl-C in the main thread) stopped it.
    """
    return simulate_settings(problem.model, problem.p, problem.settings(), record)


def simulate_settings(model: Model, p, settings: dict, record: bool = False) -> Response:
    """Simulate one run given as :func:`rocking.sim.problem.resolve` gives it, without a :class:`Problem`.

    The single-call path of :func:`rocking.simulate`: ``model``, ``p`` (the parameter vector)
    and ``settings`` (every field of :data:`~rocking.sim.boundary.CASE`, the arrays as arrays,
    lists or tuples of floats) must be as checked as a :class:`Problem`'s; they are not checked again.
    Returns and raises as :func:`simulate`.
    """
    lib = library(model)
    keep: list = []
    case = _case(settings, keep)
    params = _address(p, keep)
    result = _Result()
    capacity = _history_capacity(settings) if record else 0
    while True:
        buffers = _history_buffers(capacity, lib.ny) if record else None

        def call(stop, buffers=buffers):
            return lib.lib.rocking_simulate(
                params,
                ctypes.byref(case),
                ctypes.byref(result),
                ctypes.byref(_history(buffers)) if record else None,
                ctypes.byref(lib.control(stop)),
            )

        n = _stoppable(call, lib.lib)
        if result.status == boundary.STOPPED.value:
            raise KeyboardInterrupt("rocking.sim.c_backend.request_stop() stopped the run")
        if n < 0:  # the initial state was checked in Python: the two checks disagree
            raise SimulationError(
                f"sim.c refused the initial state y0 = {settings['y0']}, phase0 = {settings['phase0']}"
            )
        if n <= capacity:
            break
        capacity = int(n)  # the run is deterministic: the same run again, with room for all of it
    if result.status == boundary.FAILED.value:
        raise _failed(f"at t = {result.t_end:.17g}")
    return Response.from_record(
        result,
        _history_arrays(buffers, n, model.state, math.isfinite(settings["mu_s"]), bool(model.manifest.get("flight")))
        if buffers is not None  # exactly when record
        else None,
    )


def _history_buffers(capacity: int, ny: int) -> dict[str, np.ndarray]:
    return {
        "t": np.empty(capacity),
        "y": np.empty((capacity, ny)),
        "phase": np.empty(capacity, dtype=np.int32),
        "ag": np.empty(capacity),
        "floor": np.empty((capacity, len(FLOOR_BUFFER))),
        "slide": np.empty(capacity, dtype=np.int32),
        "flight": np.empty((capacity, len(FLIGHT_COLUMNS))),
    }


def _history(buffers: dict[str, np.ndarray]) -> _History:
    return _History(
        len(buffers["t"]),
        buffers["t"].ctypes.data_as(_dbl_p),
        buffers["y"].ctypes.data_as(_dbl_p),
        buffers["phase"].ctypes.data_as(_i32_p),
        buffers["ag"].ctypes.data_as(_dbl_p),
        buffers["floor"].ctypes.data_as(_dbl_p),
        buffers["slide"].ctypes.data_as(_i32_p),
        buffers["flight"].ctypes.data_as(_dbl_p),
    )


def _history_arrays(
    buffers: dict[str, np.ndarray], n: int, state, friction: bool, flight: bool = False
) -> dict[str, np.ndarray]:
    """The history's columns: ``t``, the state, ``phase``, ``ag``; on a floor with friction (``friction``: a
    finite ``mu_s``) or on any floor of a model with flight (``flight``) also
    :data:`~rocking.sim.history.FLOOR_COLUMNS`, the floor's buffer then the slip's sign; with flight then
    :data:`~rocking.sim.history.FLIGHT_COLUMNS` (docs/model.md section 16)."""
    history = {"t": buffers["t"][:n].copy()}
    for i, name in enumerate(state):
        history[name] = buffers["y"][:n, i].copy()
    history["phase"] = buffers["phase"][:n].astype(int)
    history["ag"] = buffers["ag"][:n].copy()
    if friction or flight:
        for i, name in enumerate(FLOOR_BUFFER):
            history[name] = buffers["floor"][:n, i].copy()
        history["slide"] = buffers["slide"][:n].astype(int)
    if flight:
        for i, name in enumerate(FLIGHT_COLUMNS):
            history[name] = buffers["flight"][:n, i].copy()
    return history


# --------------------------------------------------------------------------- #
# Many runs of one model                                                       #
# --------------------------------------------------------------------------- #


def _default_threads() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def _records(cases: Cases) -> np.ndarray:
    """The cases as ``rocking_case`` records; their ``atol`` point into ``cases.settings["atol"]``, their
    ``samples`` and ``extrema`` into the packed buffers (shared, not copied), ``y0`` is NULL."""
    records = np.zeros(len(cases), dtype=CASE_DTYPE)
    for f in CASE:
        if f.kind == SERIES:
            records[f.name] = cases.settings[f.name].pointers()
        elif f.kind != DOUBLES:
            records[f.name] = cases.settings[f.name]
    atol = cases.settings["atol"]
    records["atol"] = atol.ctypes.data + atol.strides[0] * np.arange(len(cases), dtype=np.uintp)
    return records


def lanes(model: str | Model = "omd") -> int:
    """The doubles per vector the batch of ``model`` runs its lanes with now: 4 (AVX2), 2 (SSE2), 8 (AVX-512F, on
    request), or 0 when it runs scalar (``ROCKING_LANES=0``, a machine other than x86-64, a model whose rocking
    accelerations the lanes cannot evaluate); ``ROCKING_LANES_ISA=sse2`` caps the width, ``avx512`` allows 8
    (rocking/sim/csrc/lanes.h)."""
    return int(library(model).lib.rocking_lanes())


def simulate_cases(cases: Cases, threads: int | None = None, lanes: bool = True) -> dict[str, np.ndarray]:
    """Simulate every case of ``cases`` from rest, without history.

    Parameters
    ----------
    cases : Cases
        The runs (see :func:`rocking.sim.cases.pulse_cases`, :meth:`Cases.of`).
    threads : int, optional
        Threads to run chunks of the batch on (the GIL is released in C);
        default all the CPUs this process may use. The results do not depend
        on it.
    lanes : bool, optional
        Integrate several cases at once over vectors (rocking/sim/csrc/lanes.h; where :func:`lanes` > 0): the
        verdicts, impacts and statuses of the scalar path, ``theta_max`` and ``x_max`` to about 1e-10 relative
        (the last bits of sin and cos). False: the scalar path, bit for bit :func:`simulate`'s.

    Returns
    -------
    dict of ndarray
        One array of shape ``(n,)`` per field of :data:`rocking.sim.problem.RESULT_FIELDS`
        (``status``: indices into :data:`rocking.sim.boundary.STATUS`).

    Raises
    ------
    CBuildError
        If the C back end cannot be built.
    SimulationError
        If the integrator fails on any run (the message lists them).
    KeyboardInterrupt
        If :func:`request_stop` (or Ctrl-C in the main thread) stopped it.
    """
    lib = library(cases.model)
    n = len(cases)
    threads = _default_threads() if threads is None else threads
    if not (isinstance(threads, (int, np.integer)) and threads >= 1):
        raise ValueError(f"threads must be an integer >= 1 (got {threads!r})")
    if not isinstance(lanes, (bool, np.bool_)):
        raise ValueError(f"lanes must be True or False (got {lanes!r})")
    records = _records(cases)
    out = np.zeros(n, dtype=RESULT_DTYPE)
    threads = min(int(threads), max(n, 1))

    def batch(stop: ctypes.c_int32) -> None:
        control = lib.control(stop)

        def run(lo: int, hi: int) -> None:
            # Row slices of C-contiguous arrays are C-contiguous: no copies.
            lib.lib.rocking_simulate_batch_lanes(
                hi - lo, cases.p[lo:hi], records[lo:hi], out[lo:hi], ctypes.byref(control), int(lanes)
            )

        if threads == 1:
            run(0, n)
            return
        # More chunks than threads: runs differ a lot in cost (an early overturn
        # against a long rocking history), small chunks keep the threads busy.
        bounds = np.linspace(0, n, min(n, 8 * threads) + 1).astype(int)
        with ThreadPoolExecutor(max_workers=threads) as pool:
            for future in [pool.submit(run, lo, hi) for lo, hi in zip(bounds[:-1], bounds[1:]) if hi > lo]:
                future.result()

    _stoppable(batch, lib.lib)
    if np.any(out["status"] == boundary.STOPPED.value):
        raise KeyboardInterrupt("rocking.sim.c_backend.request_stop() stopped the batch")
    failed = np.flatnonzero(out["status"] == boundary.FAILED.value)
    if failed.size:
        raise SimulationError(
            f"the C integrator failed on {failed.size} of {n} runs (step size underflow), e.g. run(s) "
            f"{failed[:10].tolist()}"
        )
    return {name: out[name].astype(dtype) for name, dtype in RESULT_FIELDS.items()}
