"""The ``rocking`` command (:mod:`.main`, the studies' commands in :mod:`.study`).

A process whose first import of NumPy comes through here is the command's own (the console script and ``python -m
rocking`` import this package first: ``import rocking`` loads no NumPy). There NumPy's BLAS starts one thread, not
one per core: OpenBLAS starts its threads when NumPy loads (0.05 s of CPU of every command, a quarter of ``rocking
--help``'s), and the command has no use for them. Its simulations are C (no BLAS) or NumPy on vectors; its local
workers are threads (C back end) or processes (NumPy back end), which inherit the setting: one BLAS thread each,
not a core's worth each; a Dask cluster's workers get one thread from Dask itself (its
``distributed.nanny.pre-spawn-environ``); the largest product the command computes, a fragility's bootstrap
(resamples x motions x levels), takes milliseconds on one thread. A variable already set is kept, and a process that
loaded NumPy before (a user's, a test's) is left alone.
"""

from __future__ import annotations

import gc
import os
import sys
from importlib import import_module

#: The variables that set how many threads the BLAS libraries NumPy may load start (OpenBLAS; an OpenMP build).
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")

if "numpy" not in sys.modules:
    for name in BLAS_THREADS:
        os.environ.setdefault(name, "1")

#: Whether this process is the command's own (:func:`claim_process`), where :func:`preload` may change how the
#: cyclic garbage collector treats it.
_own_process = False


def claim_process() -> None:
    """Mark this process as the command's own (``rocking.cli.main.main`` called without arguments, as the console
    script and ``python -m rocking`` do), not a caller's, and exempt what it has loaded (the command's modules,
    NumPy, its parser) from later collections (:func:`gc.freeze`, as :func:`preload` does): 0.015 s of the CPU of
    ``rocking --help`` and ``rocking simulate``, mostly the last collection at the interpreter's exit."""
    global _own_process
    _own_process = True
    gc.freeze()


def preload(*modules: str) -> None:
    """Import ``modules``, which the command is about to use, in its own process (:func:`claim_process`) with the
    cyclic garbage collector paused, then exempt every object alive from later collections (:func:`gc.freeze`).

    A library's import makes objects that live as long as the process (modules, classes, functions, tables): the
    collections its allocations trigger, the full ones that scan them again as the heap grows, and the last one at
    the interpreter's exit free none of them. On a 2 x 2 map, without a freeze, the collections cost 0.08 s of CPU
    (while xarray, pandas and matplotlib load and the figure is built) and the exit 0.17 s; frozen here and by
    :func:`claim_process`, 0.014 s and 0.035 s. Objects made later (a study's, a figure's) are collected as before.
    Elsewhere (a caller's process, whose objects are its own): nothing, the modules load where they are first used.
    """
    if not _own_process:
        return
    enabled = gc.isenabled()
    gc.disable()
    try:
        for module in modules:
            import_module(module)
    finally:
        gc.freeze()
        if enabled:
            gc.enable()
