"""Running a study's tiles: in parallel, resumable, with a progress bar.

A study splits its work into :class:`Task` s (a tile of a map, a column of a
spectrum, one frequency of the optimiser), each a call of a pure,
deterministic, module-level function on a picklable payload that calls
:func:`rocking.sim.cases.run_cases` on the whole tile. :func:`run_tiles` runs
them

- in this process (``workers=1``), on local workers (default: one per core;
  every worker calls ``run_cases`` with ``threads=1``), or on a Dask cluster
  (``scheduler`` address, or ``dask_workers`` local worker processes): the
  same function on the same payload gives the same arrays. Local workers are
  threads of this process on the C back end, which releases the GIL for a
  whole batch (no start-up, no pickling, the compiled library loaded once),
  and processes on the NumPy back end, which holds it (:func:`local_pool`);
- interruption-safe: each finished tile is written at once, atomically
  (temporary file + ``os.replace``), as ``<run folder>/<tile>.npz``; the run
  folder is named by the hash of the full configuration of the work
  (:func:`run_folder`), so a rerun with the same configuration loads the
  finished tiles instead of recomputing them, and a changed configuration
  lands in another folder and never sees stale tiles. On an interruption
  (Ctrl-C, an error) local workers get no new tiles, and the tiles they are
  running are waited for and stored too: a thread cannot be stopped inside C;
- in bounded memory: at most two tiles per worker are in flight, and each
  result is handed to the study's ``place`` callback and dropped, so a study
  holds its result arrays plus a few tiles.
"""

from __future__ import annotations

import json
import os
import signal
import tempfile
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor, wait
from contextlib import closing, contextmanager, suppress
from dataclasses import dataclass
from itertools import zip_longest
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from tqdm import tqdm

from ..model.params import ParameterError
from .config import config_hash

#: Tiles in flight per worker: one running, one queued, so no worker waits.
IN_FLIGHT_PER_WORKER = 2


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
    """

    path: Path
    fn: Callable[[object], dict]
    payload: object


@dataclass(frozen=True)
class Execution:
    """Where tiles run. Never part of a configuration: it does not change results.

    Parameters
    ----------
    workers : int, optional
        Local workers; default: every core (``os.cpu_count()``). 1 runs in this process.
        They are threads of this process on the C back end and processes on the NumPy
        back end (:func:`local_pool`).
    scheduler : str, optional
        Address of a running Dask scheduler (``"tcp://host:8786"``).
    dask_workers : int, optional
        Start a ``distributed.LocalCluster`` of this many single-threaded worker processes.
    progress : bool, optional
        Show a progress bar with an ETA (tqdm, on stderr).
    """

    workers: int | None = None
    scheduler: str | None = None
    dask_workers: int | None = None
    progress: bool = True

    def __post_init__(self) -> None:
        for name in ("workers", "dask_workers"):
            value = getattr(self, name)
            if value is not None and not (isinstance(value, int) and not isinstance(value, bool) and value >= 1):
                raise ParameterError(f"{name} must be an integer >= 1 (got {value!r})")
        if self.scheduler is not None and self.dask_workers is not None:
            raise ParameterError(
                "give either scheduler (a running Dask cluster) or dask_workers (a local one), not both"
            )
        if self.scheduler is not None and not (isinstance(self.scheduler, str) and self.scheduler):
            raise ParameterError(f"scheduler must be an address such as tcp://127.0.0.1:8786 (got {self.scheduler!r})")

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
    """What :func:`run_tiles` did: tiles computed now, tiles loaded from earlier runs, wall time (s)."""

    computed: int = 0
    reused: int = 0
    wall: float = 0.0

    def record(self) -> dict:
        return {"tiles_computed": self.computed, "tiles_reused": self.reused, "wall_s": round(self.wall, 3)}


def _atomic_write(path: Path, write: Callable) -> None:
    """Write through ``write(file)`` to a temporary file next to ``path``, then rename it over ``path``.

    A reader (or a rerun after Ctrl-C or a killed process) sees either no file
    or a whole one. No fsync: it would cost as much as a small tile's work, and
    only a power cut can leave a damaged file, which :func:`load_tile` refuses
    and the rerun recomputes.
    """
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def save_tile(path: Path, arrays: dict) -> None:
    """Store a finished tile atomically."""
    _atomic_write(path, lambda f: np.savez(f, **arrays))


def load_tile(path: Path) -> dict | None:
    """A stored tile, or ``None`` if there is none (or it cannot be read: it is then recomputed)."""
    try:
        with np.load(path) as z:
            return {k: z[k] for k in z.files}
    except (OSError, ValueError, EOFError):
        return None


def run_folder(root: str | Path, config: dict) -> Path:
    """The folder of the tiles of ``config``: ``<root>/<kind>-<part>-<hash>``, with ``config.json``.

    The name carries the first 16 hex digits of :func:`rocking.study.config.config_hash`.
    """
    name = f"{config.get('kind', 'run')}-{config.get('part', 'all')}-{config_hash(config)[:16]}"
    folder = Path(root) / name
    folder.mkdir(parents=True, exist_ok=True)
    meta = folder / "config.json"
    if not meta.is_file():
        text = json.dumps(config, indent=2, sort_keys=True) + "\n"
        _atomic_write(meta, lambda f: f.write(text.encode()))
    return folder


def _worker_init(pid: int) -> None:
    """Worker initializer: ignore Ctrl-C, and exit when process ``pid`` (the one that started the pool) is gone.

    Ctrl-C reaches the whole process group: the parent handles it, waits for
    the tiles running here and stores them; a worker stopped by it would lose
    them. A pool that is shut down stops its workers; one whose parent is
    killed (SIGKILL, SIGTERM) would leave them waiting for work forever.
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


def _local_executor(workers: int, backend: str, tasks: Sequence[Task]) -> Executor:
    """A pool of ``workers`` local workers for ``tasks`` simulated on ``backend``."""
    if local_pool(backend) == "threads":
        return ThreadPoolExecutor(workers, thread_name_prefix="rocking-tile")
    # forkserver: workers are not forked from a process that runs threads (tqdm, Dask);
    # preloading the tile functions' modules there makes later pools start at once.
    context = get_context("forkserver")
    context.set_forkserver_preload(sorted({task.fn.__module__ for task in tasks}))
    return ProcessPoolExecutor(workers, mp_context=context, initializer=_worker_init, initargs=(os.getpid(),))


@contextmanager
def _executor(execution: Execution, tasks: Sequence[Task], backend: str) -> Iterator[tuple[object, int, bool]]:
    """``(executor, slots, is_dask)`` for ``tasks`` on ``backend``; ``executor`` is ``None`` in this process."""
    if execution.uses_dask:
        from distributed import Client, LocalCluster

        cluster = None
        if execution.dask_workers is not None:
            cluster = LocalCluster(
                n_workers=execution.dask_workers,
                processes=True,
                threads_per_worker=1,
                dashboard_address=":0",  # any free port: several clusters may run at once
            )
        client = Client(cluster if cluster is not None else execution.scheduler)
        try:
            workers = sum(client.nthreads().values()) or 1
            yield client.get_executor(), IN_FLIGHT_PER_WORKER * workers, True
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    elif min(execution.local_workers, len(tasks)) <= 1:
        yield None, 1, False
    else:
        workers = min(execution.local_workers, len(tasks))
        pool = _local_executor(workers, backend, tasks)
        try:
            yield pool, IN_FLIGHT_PER_WORKER * workers, False
        finally:
            pool.shutdown(wait=True, cancel_futures=True)


def _store_unfinished(pool: Executor, in_flight: dict[Future, Task]) -> None:
    """After an interruption: cancel the queued tiles, wait for the running ones and store those that succeed.

    A thread cannot be stopped inside its C call, and a process pool's shutdown
    waits for its running tiles too: the wait is due anyway, and the tiles it
    gives spare the rerun their work.
    """
    pool.shutdown(wait=True, cancel_futures=True)
    for future, task in in_flight.items():
        if not future.cancelled() and future.exception() is None:
            # Best effort: the interruption is what to report, and a tile not stored is recomputed.
            with suppress(OSError):
                save_tile(task.path, future.result())


def _results(tasks: Sequence[Task], execution: Execution, backend: str) -> Iterator[tuple[Task, dict]]:
    """``(task, result)`` as tiles finish, with at most ``slots`` tiles submitted at a time."""
    if not tasks:
        return
    with _executor(execution, tasks, backend) as (executor, slots, is_dask):
        if executor is None:
            for task in tasks:
                yield task, task.fn(task.payload)
            return
        pending, in_flight = deque(tasks), {}
        try:
            while pending or in_flight:
                while pending and len(in_flight) < slots:
                    task = pending.popleft()
                    in_flight[executor.submit(task.fn, task.payload)] = task
                done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
                for future in done:
                    yield in_flight.pop(future), future.result()
        except BaseException:  # GeneratorExit when run_tiles stops early, KeyboardInterrupt, a tile's error
            if not is_dask:
                _store_unfinished(executor, in_flight)
            raise
        finally:
            if is_dask:
                executor.shutdown(wait=False)  # cancels what is still queued on the cluster


def interleave(*groups: Sequence[Task]) -> list[Task]:
    """The tasks of several parts (bare, damped, ...) taken in turn.

    Parts differ in cost per tile; taking them in turn keeps the rate of the
    progress bar, hence its ETA, steady.
    """
    return [task for row in zip_longest(*groups) for task in row if task is not None]


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

    Tiles already stored at ``task.path`` are loaded, not recomputed.
    ``on_tile(task)`` is called after each computed tile is stored (a hook
    for tests: raising there interrupts the run like a crash would).

    ``backend`` is the back end the tiles simulate on: it chooses threads or
    processes as local workers (:func:`local_pool`). Threads share this
    process's models and C libraries: the caller loads them first (the
    studies' :func:`rocking.study.overturning_map.preflight` does), so that each is
    built and imported once, before any thread starts, not by threads racing.

    Returns
    -------
    TileStats
    """
    start = time.perf_counter()
    stats = TileStats()
    todo = []
    for task in tasks:
        stored = load_tile(task.path) if task.path.is_file() else None
        if stored is None:
            todo.append(task)
        else:
            place(task, stored)
            stats.reused += 1
    with tqdm(total=len(tasks), initial=stats.reused, desc=desc, unit="tile", disable=not execution.progress) as bar:
        # closing(): an exception in place/on_tile must stop the workers now, not when the
        # traceback holding the generator is collected.
        with closing(_results(todo, execution, backend)) as results:
            for task, arrays in results:
                save_tile(task.path, arrays)
                place(task, arrays)
                stats.computed += 1
                bar.update()
                if on_tile is not None:
                    on_tile(task)
    stats.wall = time.perf_counter() - start
    return stats
