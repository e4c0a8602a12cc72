"""The cost of end stops: the bench map on the C path, the unlimited damper against the same damper with stops.

The map of `make bench` (50 x 50, Omega and beta in [1, 10], the reference block, gamma = 0.05,
omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8), with the paper's unlimited guide (model omd)
or with `Stops.at_edges` (model omd_stops). Prints the outcomes of both and, per response, the
instructions of the C library (load-independent) when run under callgrind::

    valgrind --tool=callgrind --callgrind-out-file=cg.free  python bench/stops_map.py free
    valgrind --tool=callgrind --callgrind-out-file=cg.stops python bench/stops_map.py stops
    callgrind_annotate --inclusive=yes cg.free | grep simulate_one      # divide by the responses

or, with ``--time``, the CPU time of the stops' map over the free one in paired runs (median of
``--pairs``), the batch's lanes on and off (``ROCKING_LANES=0`` in the environment also turns them off)::

    python bench/stops_map.py stops --time
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from rocking import Block, Damper, Stops
from rocking.sim.cases import pulse_cases, run_cases


def cases(kind: str, n: int):
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    Omega, beta = np.meshgrid(np.linspace(1, 10, n), np.linspace(1, 10, n), indexing="ij")
    params = damper.as_params()
    if kind == "stops":
        params = {**params, **Stops.at_edges(block, damper).as_params()}
    model = "omd_stops" if kind == "stops" else "omd"
    return block, pulse_cases(block, Omega, beta, model=model, params=params, rtol=1e-8)


def paired_ratio(n: int, pairs: int, lanes: bool) -> tuple[float, dict]:
    """The median over ``pairs`` paired runs of the stops' map's CPU time over the free one's (C path, one thread),
    and the stops' map's results (those of the last run)."""
    _, free = cases("free", n)
    _, stopped = cases("stops", n)
    for kind in ("free", "stops"):  # build and load outside the timing
        run_cases(cases(kind, 1)[1], "c", 1, lanes)
    ratios, res = [], {}
    for _ in range(pairs):
        start = time.process_time()
        run_cases(free, "c", 1, lanes)
        middle = time.process_time()
        res = run_cases(stopped, "c", 1, lanes)
        ratios.append((time.process_time() - middle) / (middle - start))
    return float(np.median(ratios)), res


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kind", choices=["free", "stops"])
    parser.add_argument("-n", type=int, default=50, help="grid size per axis (default 50)")
    parser.add_argument("--time", action="store_true", help="the CPU time over the free map's, lanes on and off")
    parser.add_argument("--pairs", type=int, default=5, help="paired runs of --time (default 5)")
    args = parser.parse_args(argv)
    if args.time:
        for lanes in (True, False):
            ratio, _ = paired_ratio(args.n, args.pairs, lanes)
            print(f"stops over free, lanes {'on' if lanes else 'off'}: {ratio:.3f}x CPU (median of {args.pairs} pairs)")
        return 0
    block, batch = cases(args.kind, args.n)
    start = time.perf_counter()
    res = run_cases(batch, "c", 1)
    seconds = time.perf_counter() - start
    beyond = int((res["x_max"] > block.B / 2).sum())
    print(
        f"{args.kind}: {len(batch)} responses, overturned {int(res['overturned'].sum())}, stroke beyond B/2 "
        f"{beyond}, stop contacts {int(res['stop_contacts'].sum())}, {seconds:.2f} s of C (wall, one thread)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
