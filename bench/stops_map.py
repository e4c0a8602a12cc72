"""The cost of end stops: the bench map on the C path, the unlimited damper against the same damper with stops.

The map of `make bench` (50 x 50, Omega and beta in [1, 10], the reference block, gamma = 0.05,
omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8), with the paper's unlimited guide (model omd)
or with `Stops.at_edges` (model omd_stops). Prints the outcomes of both and, per response, the
instructions of the C library (load-independent) when run under callgrind::

    valgrind --tool=callgrind --callgrind-out-file=cg.free  python bench/stops_map.py free
    valgrind --tool=callgrind --callgrind-out-file=cg.stops python bench/stops_map.py stops
    callgrind_annotate --inclusive=yes cg.free | grep simulate_one      # divide by the responses

or the wall time of one C pass without it (``--time``).
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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kind", choices=["free", "stops"])
    parser.add_argument("-n", type=int, default=50, help="grid size per axis (default 50)")
    args = parser.parse_args(argv)
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
