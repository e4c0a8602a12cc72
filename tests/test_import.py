"""``import rocking`` is quick: the heavy libraries load when a function needs them, not at import."""

from __future__ import annotations

import subprocess
import sys
import time

#: Libraries ``import rocking`` must not load: each costs from a tenth of a second to a second.
HEAVY = ("scipy", "pandas", "xarray", "matplotlib", "dask", "netCDF4", "sympy", "jinja2")

#: ``import rocking`` against ``import numpy``, which it needs anyway (best of several runs each): 2.6 measured
#: on the 2-core development machine while it ran other work (4.8 s in all before the lazy imports of SciPy).
RATIO = 4.0


def _best(code: str, runs: int = 3) -> float:
    best = float("inf")
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        best = min(best, time.perf_counter() - start)
    return best


def test_import_loads_no_heavy_library():
    code = "import sys, rocking; print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = set(run.stdout.split())
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


def test_import_costs_little_more_than_numpy():
    assert _best("import rocking") < RATIO * _best("import numpy")
