"""Running a study's tiles: in parallel, resumable, with a progress bar.

A study splits its work into :class:`Task` s (a tile of a map, a column of a
spectrum, one frequency of the optimiser), each a call of a pure,
deterministic, module-level function on a picklable payload that calls
:func:`rocking.sim.cases.run_cases` on the whole tile. :func:`run_tiles` runs
them

- on local workers (default: one per core; every worker calls ``run_cases``
  with ``threads=1``) or on a Dask cluster (``scheduler`` address, or
  ``dask_workers`` local worker processes): the same function on the same
  payload gives the same arrays. Local workers are threads of this process on
  the C back end, which releases the GIL for a whole batch (no start-up, no
  pickling, the compiled library loaded once), and processes on the NumPy back
  end, which holds it (:func:`local_pool`); one worker is this thread;
- resumably: each finished tile is written at once, atomically, as
  ``<run folder>/<tile>.npz`` with a manifest (its place, the names, shapes
  and dtypes of its arrays, their checksum: :func:`save_tile`); the run folder
  is named by the hash of the full configuration of the work
  (:func:`run_folder`), so a rerun with the same configuration loads the
  finished tiles instead of recomputing them, and a changed configuration
  lands in another folder and never sees stale tiles. A stored tile that does
  not match its manifest or what its task expects (:func:`load_tile`, which
  reads no more than its arrays' size) is computed again, with a
  :class:`TileWarning`. A tile that does not fit on the disk ends the run with
  :class:`~rocking.study.storage.DiskFull`, the tiles stored so far kept;
- interruptibly: on Ctrl-C the C runs of this process are stopped
  (:func:`rocking.sim.c_backend.request_stop`), worker processes are
  terminated and queued tiles cancelled, so the study ends at once; finished
  tiles are on disk already, and :class:`Interrupted` says how many. On an
  error instead, the running tiles are waited for and stored too;
- in bounded memory: at most two tiles per worker are in flight, and each
  result is handed to the study's ``place`` callback and dropped, so a study
  holds its result arrays plus a few tiles.
"""

from __future__ import annotations

import json
import logging
import math
import os
import signal
import threading
import time
import warnings
from collections import deque
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor, wait
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from itertools import zip_longest
from multiprocessing import get_context
from pathlib import Path

import numpy as np

from ..model.params import ParameterError
from .config import config_hash
from .files import (
    MAX_NPY_HEADER,
    MAX_STUDY_BYTES,
    UNREADABLE,
    DiskFull,
    atomic_write,
    checksum,
    describe,
    layout,
    make_folder,
    read_npz,
)

#: Tiles in flight per worker: one running, one queued, so no worker waits.
IN_FLIGHT_PER_WORKER = 2

#: Upper bound of ``workers`` and ``dask_workers``: more is a typo, not a machine.
MAX_WORKERS = 1024

#: Seconds to wait for a Dask scheduler to answer (Dask's own default, 30 s, is long for a typo).
SCHEDULER_TIMEOUT = 5.0

#: How to get the optional Dask extra.
DASK_INSTALL = 'pip install "rocking[dask]"'

#: Name of the manifest inside a stored tile, and its version.
MANIFEST = "__tile__"
TILE_FORMAT = 1

#: Bytes of a stored tile besides its arrays' values: the manifest (names, shapes, checksum) and the headers.
TILE_OVERHEAD = 1 << 20


class TileWarning(UserWarning):
    """A stored tile is damaged or foreign (unreadable, changed, misplaced, wrong shape): it is computed again."""


class DamagedTile(ValueError):
    """Why a stored tile cannot be used (:func:`load_tile`); :func:`run_tiles` recomputes it."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C stopped a study; its finished tiles are kept on disk, and a rerun resumes from them.

    Attributes
    ----------
    kept : int
        Tiles of the study on disk (found at the start, or finished before the interruption).
    total : int
        Tiles of the study.
    folder : Path
        Where they are: the folder of the study's run folders.
    """

    def __init__(self, kept: int, total: int, folder: Path) -> None:
        super().__init__(f"interrupted: {kept} of {total} tiles kept in {folder}")
        self.kept, self.total, self.folder = kept, total, folder


@dataclass(frozen=True)
class Task:
    """One tile of work.

    Attributes
    ----------
    path : Path
        Where the finished tile is stored (inside its run folder).
    fn : callable
        Module-level pure function ``fn(payload) -> dict of ndarray``.
    payload : object
        Its picklable argument.
    expect : mapping of str to tuple of int, optional
        The arrays ``fn`` returns, name -> shape: a stored tile with other
        names or shapes is computed again. ``None``: not checked.
    """

    path: Path
    fn: Callable[[object], dict]
    payload: object
    expect: Mapping[str, tuple[int, ...]] | None = field(default=None, compare=False)


def _count(name: str, value, optional: bool = True) -> None:
    """Refuse a worker count that is not an integer in [1, MAX_WORKERS]."""
    if value is None and optional:
        return
    ok = isinstance(value, (int, np.integer)) and not isinstance(value, bool) and 1 <= value <= MAX_WORKERS
    if not ok:
        raise ParameterError(f"{name} must be an integer in [1, {MAX_WORKERS}] (got {value!r})")


def _import_distributed():
    """The ``distributed`` package, or a ParameterError saying how to install it."""
    try:
        import distributed
    except ModuleNotFoundError as exc:
        if (exc.name or "").partition(".")[0] not in ("dask", "distributed"):
            raise
        raise ParameterError(
            f"scheduler (--scheduler) and dask_workers (--dask-workers) run on Dask, which is not installed "
            f"(no module {exc.name}): {DASK_INSTALL}"
        ) from None
    return distributed


@dataclass(frozen=True)
class Execution:
    """Where tiles run. Never part of a configuration: it does not change results.

    Parameters
    ----------
    workers : int, optional
        Local workers, in [1, :data:`MAX_WORKERS`]; default: every core
        (``os.cpu_count()``). They are threads of this process on the C back
        end and processes on the NumPy back end (:func:`local_pool`).
    scheduler : str, optional
        Address of a running Dask scheduler (``"tcp://host:8786"``); it must
        answer within :data:`SCHEDULER_TIMEOUT` seconds.
    dask_workers : int, optional
        Start a ``distributed.LocalCluster`` of this many single-threaded worker processes.
    progress : bool, optional
        Show a progress bar with an ETA (tqdm, on stderr).

    Raises
    ------
    ParameterError
        For a count that is not an integer in range, both ``scheduler`` and
        ``dask_workers``, a scheduler that is not an address, or Dask asked
        for and not installed (the ``dask`` extra).
    """

    workers: int | None = None
    scheduler: str | None = None
    dask_workers: int | None = None
    progress: bool = True

    def __post_init__(self) -> None:
        _count("workers", self.workers)
        _count("dask_workers", self.dask_workers)
        if self.scheduler is not None and self.dask_workers is not None:
            raise ParameterError(
                "give either scheduler (a running Dask cluster) or dask_workers (a local one), not both"
            )
        if self.scheduler is not None and not (isinstance(self.scheduler, str) and self.scheduler.strip()):
            raise ParameterError(f"scheduler must be an address such as tcp://127.0.0.1:8786 (got {self.scheduler!r})")
        if not isinstance(self.progress, bool):
            raise ParameterError(f"progress must be True or False (got {self.progress!r})")
        if self.uses_dask:
            _import_distributed()  # now, not after the tiles are loaded and the back end checked

    @property
    def local_workers(self) -> int:
        """Local workers (threads or processes) when Dask is not used."""
        return self.workers or os.cpu_count() or 1

    @property
    def uses_dask(self) -> bool:
        return self.scheduler is not None or self.dask_workers is not None


#: Default execution: local workers on every core, with a progress bar.
LOCAL = Execution()


@dataclass
class TileStats:
    """What :func:`run_tiles` did: tiles computed now, tiles loaded from earlier runs, wall time (s).

    ``salvaged``: tiles that finished while an interruption or an error was being handled (stored, not placed).
    """

    computed: int = 0
    reused: int = 0
    wall: float = 0.0
    salvaged: int = 0

    def record(self) -> dict:
        return {"tiles_computed": self.computed, "tiles_reused": self.reused, "wall_s": round(self.wall, 3)}


# --- stored tiles ------------------------------------------------------------------------------


def _place(path: Path) -> str:
    """A tile's place, stored in its manifest: a tile copied or moved to another place is refused."""
    return f"{path.parent.name}/{path.name}"


def save_tile(path: Path, arrays: dict) -> None:
    """Store a finished tile atomically, with its manifest: place, names, shapes, dtypes, checksum."""
    manifest = {"format": TILE_FORMAT, "tile": _place(path), "arrays": layout(arrays), "sha256": checksum(arrays)}
    text = np.array(json.dumps(manifest, sort_keys=True))  # a 0-d unicode array: no pickle needed to read it
    atomic_write(path, lambda f: np.savez(f, **arrays, **{MANIFEST: text}))


def _manifest(stored: dict) -> dict:
    """The manifest of a stored tile, taken out of its arrays."""
    text = stored.pop(MANIFEST, None)
    if text is None or text.dtype.kind != "U" or text.shape != ():
        raise DamagedTile("no manifest: not written by this version of rocking")
    try:
        manifest = json.loads(str(text))
    except ValueError:
        manifest = None
    if not isinstance(manifest, dict) or manifest.get("format") != TILE_FORMAT:
        raise DamagedTile(f"its manifest is not a tile manifest of format {TILE_FORMAT}")
    return manifest


def _check_expected(arrays: dict, expect: Mapping[str, tuple[int, ...]]) -> None:
    """Refuse arrays that are not those a task returns: other names, or other shapes."""
    if set(arrays) != set(expect):
        raise DamagedTile(f"arrays {', '.join(sorted(arrays))}, expected {', '.join(sorted(expect))}")
    wrong = [k for k in sorted(expect) if tuple(arrays[k].shape) != tuple(expect[k])]
    if wrong:
        k = wrong[0]
        raise DamagedTile(f"array {k} has shape {arrays[k].shape}, expected {tuple(expect[k])}")


def load_tile(path: Path, expect: Mapping[str, tuple[int, ...]] | None = None) -> dict:
    """A stored tile's arrays, checked against its manifest and against ``expect`` (name -> shape).

    Raises
    ------
    DamagedTile
        With the reason: unreadable (truncated, damaged, not an archive), no
        manifest, written for another place, arrays or content that differ from
        the manifest (checksum), or names and shapes other than ``expect``.
    """
    # Every array of a tile has at most 8 bytes per value: a tile larger than that is refused from its headers.
    limit = MAX_STUDY_BYTES if expect is None else sum(8 * math.prod(s) + MAX_NPY_HEADER for s in expect.values())
    try:
        stored = read_npz(path, limit + TILE_OVERHEAD)
    except UNREADABLE as exc:
        raise DamagedTile(f"unreadable ({describe(exc)})") from None
    manifest = _manifest(stored)
    if manifest.get("tile") != _place(path):
        raise DamagedTile(f"it is the tile {manifest.get('tile')!r}, stored in another place")
    if manifest.get("arrays") != layout(stored):
        raise DamagedTile("its arrays differ from its manifest")
    if manifest.get("sha256") != checksum(stored):
        raise DamagedTile("its content does not match its checksum")
    if expect is not None:
        _check_expected(stored, expect)
    return stored


def _stored(task: Task) -> dict | None:
    """The stored tile of ``task``, or ``None`` (none yet, or damaged: then with a :class:`TileWarning`)."""
    if not task.path.is_file():
        return None
    try:
        return load_tile(task.path, task.expect)
    except DamagedTile as exc:
        warnings.warn(f"{task.path}: damaged tile ({exc}); computing it again", TileWarning, stacklevel=4)
        return None


def run_folder(root: str | Path, config: dict) -> Path:
    """The folder of the tiles of ``config``: ``<root>/<kind>-<part>-<hash>``, with ``config.json``.

    The name carries the first 16 hex digits of :func:`rocking.study.config.config_hash`.

    Raises
    ------
    ParameterError
        If the folder cannot be created or written.
    """
    name = f"{config.get('kind', 'run')}-{config.get('part', 'all')}-{config_hash(config)[:16]}"
    folder = make_folder(Path(root) / name, "tiles folder")
    meta = folder / "config.json"
    if not meta.is_file():
        text = json.dumps(config, indent=2, sort_keys=True) + "\n"
        atomic_write(meta, lambda f: f.write(text), mode="w")
    return folder


# --- local workers and Dask ----------------------------------------------------------------------


def _worker_init(pid: int) -> None:
    """Worker initializer: ignore Ctrl-C, and exit when process ``pid`` (the one that started the pool) is gone.

    Ctrl-C reaches the whole process group: the parent handles it (it
    terminates its workers); a worker stopped by it in the middle of sending a
    result could leave the pool broken for the parent's clean-up. A pool that
    is shut down stops its workers; one whose parent is killed (SIGKILL,
    SIGTERM) would leave them waiting for work forever.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)

    def watch() -> None:
        while True:
            time.sleep(1.0)
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


def local_pool(backend: str) -> str:
    """The local workers of tiles simulated on ``backend``: ``"threads"`` or ``"processes"``.

    The C back end releases the GIL for a whole batch, so threads of this
    process run tiles in parallel, without a pool to start, payloads to pickle
    or a library to load per worker. The NumPy back end holds the GIL: only
    processes run it in parallel.

    Parameters
    ----------
    backend : {"c", "numpy"}
        :attr:`rocking.study.config.Setting.backend` of the study.

    Returns
    -------
    str
    """
    return "threads" if backend == "c" else "processes"


def _stop_c_runs() -> None:
    """Stop every C run of this process now: worker threads cannot be stopped otherwise."""
    from ..sim import backends

    backends.request_stop()


def _terminate(pool: ProcessPoolExecutor) -> None:
    """Terminate the processes of ``pool`` now, running tiles lost (Python < 3.14 has no public way)."""
    terminate = getattr(pool, "terminate_workers", None)
    if terminate is not None:
        terminate()
        return
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        with suppress(OSError, ValueError):  # already gone
            process.terminate()


class Stopped(RuntimeError):
    """A tile stopped on a Dask worker by :func:`rocking.sim.c_backend.request_stop` (after Ctrl-C)."""


def _on_dask(fn: Callable[[object], dict], payload: object) -> dict:
    """``fn(payload)`` on a Dask worker, where a KeyboardInterrupt (a stopped C run) would kill the worker process."""
    try:
        return fn(payload)
    except KeyboardInterrupt:
        raise Stopped("stopped after Ctrl-C") from None


class _Workers:
    """Where tiles run (``kind``: ``"here"``, ``"threads"``, ``"processes"``, ``"dask"``), and the tiles in flight.

    ``slots`` tiles are submitted at a time; :meth:`results` hands them over as
    they finish. After an exception, :meth:`interrupt` (Ctrl-C: stop now) or
    :meth:`drain` (an error: let the running tiles finish) stores, through
    ``store(task, arrays)``, the tiles that finished and were not handed over.
    """

    def __init__(self, executor: Executor | None, slots: int, kind: str, store: Callable[[Task, dict], None]):
        self.executor, self.slots, self.kind, self.store = executor, slots, kind, store
        self.in_flight: dict[Future, Task] = {}

    def results(self, tasks: Sequence[Task]) -> Iterator[tuple[Task, dict]]:
        """``(task, arrays)`` as tiles finish."""
        if self.executor is None:
            for task in tasks:
                yield task, task.fn(task.payload)
            return
        pending = deque(tasks)
        while pending or self.in_flight:
            while pending and len(self.in_flight) < self.slots:
                task = pending.popleft()
                call = (_on_dask, task.fn) if self.kind == "dask" else (task.fn,)
                self.in_flight[self.executor.submit(*call, task.payload)] = task
            done, _ = wait(self.in_flight, return_when=FIRST_COMPLETED)
            for future in done:
                task = self.in_flight.pop(future)
                yield task, future.result()

    def interrupt(self) -> None:
        """Ctrl-C: stop the running tiles and cancel the queued ones, at once; store those that finished."""
        if self.kind == "threads":
            from ..sim import backends

            # A worker thread may take a queued tile after the stop: halted() stops its C call too.
            with backends.halted():
                self.drain()
            return
        if self.kind == "processes":
            _terminate(self.executor)
        self.drain()

    def drain(self) -> None:
        """Cancel the queued tiles, wait for the running local ones (after an error: they finish) and store them.

        Tiles running on Dask are cancelled, not waited for: the cluster may be busy with others' work.
        """
        if self.kind == "dask":
            self.executor.shutdown(wait=False)  # Dask's executor has no cancel_futures: this cancels
        elif self.executor is not None:
            self.executor.shutdown(wait=True, cancel_futures=True)
        for future, task in self.in_flight.items():
            if future.done() and not future.cancelled() and future.exception() is None:
                # Best effort: the interruption is what to report, and a tile not stored is recomputed.
                with suppress(OSError):
                    self.store(task, future.result())
        self.in_flight.clear()


def _local_executor(workers: int, backend: str, tasks: Sequence[Task]) -> Executor:
    """A pool of ``workers`` local workers for ``tasks`` simulated on ``backend``."""
    if local_pool(backend) == "threads":
        return ThreadPoolExecutor(workers, thread_name_prefix="rocking-tile")
    # forkserver: workers are not forked from a process that runs threads (tqdm, Dask);
    # preloading the tile functions' modules there makes later pools start at once.
    context = get_context("forkserver")
    context.set_forkserver_preload(sorted({task.fn.__module__ for task in tasks}))
    return ProcessPoolExecutor(workers, mp_context=context, initializer=_worker_init, initargs=(os.getpid(),))


def _connect(distributed, address: str):
    """A client of the scheduler at ``address``, or a one-line ParameterError after :data:`SCHEDULER_TIMEOUT`."""
    try:
        return distributed.Client(address, timeout=SCHEDULER_TIMEOUT)
    except (OSError, ValueError, TypeError) as exc:  # TimeoutError is an OSError
        raise ParameterError(
            f"scheduler {address}: no Dask scheduler answered within {SCHEDULER_TIMEOUT:g} s ({describe(exc)}); "
            "check the address and that the scheduler runs (dask scheduler)"
        ) from None


@contextmanager
def _dask(execution: Execution) -> Iterator[tuple[Executor, int]]:
    """``(executor, workers)`` of the Dask cluster of ``execution``: a running one, or a local one started here."""
    distributed = _import_distributed()
    cluster = None
    if execution.dask_workers is not None:
        cluster = distributed.LocalCluster(
            n_workers=execution.dask_workers,
            processes=True,
            threads_per_worker=1,
            dashboard_address=":0",  # any free port: several clusters may run at once
            silence_logs=logging.ERROR,  # not a warning per tile cancelled by Ctrl-C
        )
    try:
        client = distributed.Client(cluster) if cluster is not None else _connect(distributed, execution.scheduler)
        try:
            yield client.get_executor(), sum(client.nthreads().values()) or 1
        except KeyboardInterrupt:
            if cluster is not None:
                # The local workers' tiles, cancelled, still run in C, and closing would wait for them. Never
                # on a running cluster: its other clients' C runs would stop too.
                with suppress(Exception):
                    client.run(_stop_c_runs)
            raise
        finally:
            client.close()
    finally:
        if cluster is not None:
            cluster.close()


@contextmanager
def _executor(
    execution: Execution, tasks: Sequence[Task], backend: str, store: Callable[[Task, dict], None]
) -> Iterator[_Workers]:
    """The :class:`_Workers` of ``tasks`` on ``backend``; on leaving, the queued tiles are cancelled.

    Ctrl-C inside stops the running tiles at once (:meth:`_Workers.interrupt`);
    any other exception lets the local ones finish (:meth:`_Workers.drain`).
    Both store the tiles that finished, and re-raise.
    """
    with _pool(execution, tasks, backend, store) as workers:
        try:
            yield workers
        except KeyboardInterrupt:
            workers.interrupt()
            raise
        except BaseException:
            workers.drain()
            raise


@contextmanager
def _pool(
    execution: Execution, tasks: Sequence[Task], backend: str, store: Callable[[Task, dict], None]
) -> Iterator[_Workers]:
    """Start the workers of ``tasks`` and shut them down on leaving."""
    if not tasks:  # every tile was stored already: no worker, no cluster to start
        yield _Workers(None, 1, "here", store)
        return
    if execution.uses_dask:
        with _dask(execution) as (executor, workers):
            try:
                yield _Workers(executor, IN_FLIGHT_PER_WORKER * workers, "dask", store)
            finally:
                executor.shutdown(wait=False)  # cancels what is still queued on the cluster
        return
    workers = min(execution.local_workers, len(tasks))
    if workers <= 1:
        # In this thread, Ctrl-C stops a tile at once: NumPy runs Python, and the C back end waits for
        # its C calls in short slices from the main thread (rocking.sim.c_backend).
        yield _Workers(None, 1, "here", store)
        return
    pool = _local_executor(workers, backend, tasks)
    try:
        yield _Workers(pool, IN_FLIGHT_PER_WORKER * workers, local_pool(backend), store)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def interleave(*groups: Sequence[Task]) -> list[Task]:
    """The tasks of several parts (bare, damped, ...) taken in turn.

    Parts differ in cost per tile; taking them in turn keeps the rate of the
    progress bar, hence its ETA, steady.
    """
    return [task for row in zip_longest(*groups) for task in row if task is not None]


def _root(tasks: Sequence[Task]) -> Path:
    """The folder that holds every run folder of ``tasks``."""
    return Path(os.path.commonpath([task.path.parent for task in tasks])) if tasks else Path(".")


def run_tiles(
    tasks: Sequence[Task],
    place: Callable[[Task, dict], None],
    execution: Execution,
    *,
    backend: str,
    desc: str = "tiles",
    on_tile: Callable[[Task], None] | None = None,
) -> TileStats:
    """Run ``tasks``, handing every tile's arrays to ``place(task, arrays)``.

    Tiles already stored at ``task.path`` are loaded, not recomputed; a stored
    tile that is damaged or foreign (:func:`load_tile`) is computed again, with
    a :class:`TileWarning`. ``on_tile(task)`` is called after each computed
    tile is stored (a hook for tests: raising there interrupts the run like a
    crash would).

    ``backend`` is the back end the tiles simulate on: it chooses threads or
    processes as local workers (:func:`local_pool`). Threads share this
    process's models and C libraries: the caller loads them first (the
    studies' :func:`rocking.study.overturning_map.preflight` does), so that each is
    built and imported once, before any thread starts, not by threads racing.

    Returns
    -------
    TileStats

    Raises
    ------
    Interrupted
        On Ctrl-C (a KeyboardInterrupt), after stopping the workers; the tiles
        finished so far are stored.
    DiskFull
        When a tile does not fit on the disk, after the running tiles finished and
        were stored if they fit; ``kept`` counts the tiles on disk in the run folders.
    """
    start = time.perf_counter()
    stats = TileStats()

    def store(task: Task, arrays: dict) -> None:
        save_tile(task.path, arrays)
        stats.salvaged += 1

    try:
        todo = _reuse(tasks, place, stats)
        with (
            _progress_bar(execution.progress, total=len(tasks), initial=stats.reused, desc=desc, unit="tile") as bar,
            _executor(execution, todo, backend, store) as workers,
        ):
            for task, arrays in workers.results(todo):
                save_tile(task.path, arrays)
                stats.computed += 1
                place(task, arrays)
                bar.update()
                if on_tile is not None:
                    on_tile(task)
    except KeyboardInterrupt as exc:
        raise Interrupted(stats.reused + stats.computed + stats.salvaged, len(tasks), _root(tasks)) from exc
    except DiskFull as exc:
        raise DiskFull(exc.path, kept=_kept(tasks)) from None
    stats.wall = time.perf_counter() - start
    return stats


class _NoBar:
    """The progress bar of a run without one (``progress=False``): tqdm is then not imported."""

    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *exc) -> None:
        return None

    def update(self, n: int = 1) -> None:
        return None


def _progress_bar(shown: bool, **options):
    """A tqdm progress bar of ``options`` on stderr if ``shown``, else one that shows nothing: tqdm.auto is
    imported only for a bar shown (it and the asyncio and notebook checks it imports cost a command 15 ms)."""
    if not shown:
        return _NoBar()
    from tqdm.auto import tqdm

    return tqdm(**options)


def _kept(tasks: Sequence[Task]) -> int:
    """The tiles on disk in the run folders of ``tasks``: this call's, and those of earlier calls of the study
    (the rounds of an adaptive map) that a rerun reuses too."""
    folders = {task.path.parent for task in tasks}
    return sum(1 for folder in folders for _ in folder.glob("*.npz"))


def _reuse(tasks: Sequence[Task], place: Callable[[Task, dict], None], stats: TileStats) -> list[Task]:
    """Place the stored tiles of ``tasks``; the tasks left to compute."""
    todo = []
    for task in tasks:
        stored = _stored(task)
        if stored is None:
            todo.append(task)
        else:
            place(task, stored)
            stats.reused += 1
    return todo
