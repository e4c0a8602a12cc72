"""Where a study's CPU goes: inside the C batch calls, generating motions, and the rest (Python).

`python bench/split.py [--map N] [--fragility N]`: a full ``N x N`` overturning map (the bench map's block and
damper, both directions) and a fragility of ``N`` stochastic motions (4 PGA levels, both directions), each on one
worker in this process, after a warm-up that builds and loads the C libraries. The CPU of this process is split by
timing every call of the C batch (``rocking_simulate_batch_lanes``, which the batch calls, lanes or not) and every
stochastic motion drawn; imports are done before and excluded (they are a fixed cost of a process, about 1.5 s of
CPU with xarray, pandas and matplotlib, whatever the study's size). CPU time, not wall time: the machine is shared.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
import tempfile
import time
import warnings

sys.path.insert(0, os.path.dirname(__file__))

import dask.array  # noqa: E402, F401  (imported by xarray on its first Dataset: excluded from the split)
import xarray  # noqa: E402, F401
from bench_map import GAMMA, H_MASS, OMEGA_RATIO, ZETA  # noqa: E402

from rocking.model.params import Block  # noqa: E402
from rocking.model.stochastic import SiteModel  # noqa: E402
from rocking.sim import c_backend  # noqa: E402
from rocking.study import suite as suite_module  # noqa: E402
from rocking.study.config import Grid, Setting, Tuning  # noqa: E402
from rocking.study.fragility import FitWarning  # noqa: E402
from rocking.study.ida import incremental_dynamic_analysis  # noqa: E402
from rocking.study.overturning_map import overturning_map  # noqa: E402
from rocking.study.suite import Suite  # noqa: E402
from rocking.study.tiles import Execution  # noqa: E402

#: The fragility's site model: short motions (10 s at 0.01 s), as the memory bench of bench/run.py.
SITE = SiteModel(arias=0.3, d595=4.0, t_mid=3.0, f_mid=4.0, f_slope=-0.1, zeta_f=0.25, dt=0.01, duration=10.0)


@contextlib.contextmanager
def timing():
    """Yield a dict that collects the CPU seconds spent in the C batch calls and in drawing stochastic motions."""
    spent = {"c_s": 0.0, "responses": 0, "motions_s": 0.0, "motions": 0}
    library, synthesize, wrapped = c_backend.library, suite_module.synthesize, set()

    def timed_library(*args, **kwargs):
        lib = library(*args, **kwargs)
        if id(lib) not in wrapped:
            wrapped.add(id(lib))
            batch = lib.lib.rocking_simulate_batch_lanes

            def timed_batch(n, *rest):
                start = time.process_time()
                batch(n, *rest)
                spent["c_s"] += time.process_time() - start
                spent["responses"] += n

            lib.lib.rocking_simulate_batch_lanes = timed_batch
        return lib

    def timed_synthesize(*args, **kwargs):
        start = time.process_time()
        out = synthesize(*args, **kwargs)
        spent["motions_s"] += time.process_time() - start
        spent["motions"] += 1
        return out

    c_backend.library, suite_module.synthesize = timed_library, timed_synthesize
    try:
        yield spent
    finally:
        c_backend.library, suite_module.synthesize = library, synthesize


def _split(run) -> dict:
    """``run()`` once to warm up, then once timed: its CPU seconds, split."""
    run(warm_up=True)
    with timing() as spent:
        start = time.process_time()
        run(warm_up=False)
        spent["cpu_s"] = time.process_time() - start
    spent["other_s"] = spent["cpu_s"] - spent["c_s"] - spent["motions_s"]
    spent["other_fraction"] = spent["other_s"] / spent["cpu_s"]
    return spent


def map_split(n: int) -> dict:
    """The CPU split of a full ``n x n`` map, block alone and with the damper, both directions, 1 worker."""
    setting, tuning = Setting(Block.reference()), Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS)

    def run(warm_up: bool) -> None:
        side = 4 if warm_up else n
        grids = Grid("Omega", 1.0, 10.0, side), Grid("beta", 1.0, 10.0, side)
        with tempfile.TemporaryDirectory() as runs:
            overturning_map(setting, tuning, *grids, Execution(workers=1, progress=False), runs=runs, full=True)

    return {"n": n, **_split(run)}


def fragility_split(n: int) -> dict:
    """The CPU split of a fragility over ``n`` stochastic motions x 4 PGA levels, both directions, 1 worker."""
    setting, tuning = Setting(Block.reference(), t_after=5.0), Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS)

    def run(warm_up: bool) -> None:
        with tempfile.TemporaryDirectory() as runs, warnings.catch_warnings():
            if warm_up:  # a fit to 2 motions: rightly warned of, and beside the point here
                warnings.simplefilter("ignore", FitWarning)
            incremental_dynamic_analysis(
                setting,
                tuning,
                Suite.stochastic(SITE, 2 if warm_up else n, seed=1),
                Grid("pga", 1.0, 8.0, 4),
                Execution(workers=1, progress=False),
                measure_name="pga",
                runs=runs,
            )

    return {"n": n, **_split(run)}


def describe(name: str, split: dict) -> str:
    """One line of a split, in percent of the CPU."""
    cpu = split["cpu_s"]
    motions = f", motions {100 * split['motions_s'] / cpu:.1f} %" if split["motions"] else ""
    return (
        f"{name}: CPU {cpu:.2f} s: C batch {100 * split['c_s'] / cpu:.1f} % ({split['responses']} responses)"
        f"{motions}, the rest (Python) {100 * split['other_fraction']:.1f} %"
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", type=int, default=200, help="side of the map (default 200)")
    parser.add_argument("--fragility", type=int, default=200, help="stochastic motions (default 200)")
    parser.add_argument("--json", help="write the splits to this file")
    args = parser.parse_args(argv)
    splits = {"map": map_split(args.map), "fragility": fragility_split(args.fragility)}
    print(describe(f"{args.map}x{args.map} map, 1 worker", splits["map"]))
    print(describe(f"fragility of {args.fragility} stochastic motions, 1 worker", splits["fragility"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(splits, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
