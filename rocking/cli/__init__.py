"""The ``rocking`` command (:mod:`.main`, the studies' commands in :mod:`.study`).

A process whose first import of NumPy comes through here is the command's own (the console script and ``python -m
rocking`` import this package first: ``import rocking`` loads no NumPy). There NumPy's BLAS starts one thread, not
one per core: OpenBLAS starts its threads when NumPy loads (0.05 s of CPU of every command, a third of ``rocking
--help``'s), and the command has no use for them. Its simulations are C (no BLAS) or NumPy on vectors; its local
workers are processes, one per core, which inherit the setting (one BLAS thread each, not a core's worth each);
a Dask cluster's workers get one thread from Dask itself (its ``distributed.nanny.pre-spawn-environ``); the largest
product the command computes, a fragility's bootstrap (resamples x motions x levels), takes milliseconds on one
thread. A variable already set is kept, and a process that loaded NumPy before (a user's, a test's) is left alone.
"""

import os
import sys

#: The variables that set how many threads the BLAS libraries NumPy may load start (OpenBLAS; an OpenMP build).
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")

if "numpy" not in sys.modules:
    for name in BLAS_THREADS:
        os.environ.setdefault(name, "1")
