"""The cost of end stops: the bench map on the C path, the unlimited damper against the same damper with stops.

The map of `make bench` (50 x 50, Omega and beta in [1, 10], the reference block, gamma = 0.05,
omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8), with the paper's unlimited guide (model omd)
or with `Stops.at_edges` (model omd_stops; with ``--law hunt-crossley``, omd_stops_hc: Hunt-Crossley pads of
the same restitution, outcomes and instructions only). Prints the outcomes of both and, per response, the
instructions of the C library (load-independent) when run under callgrind: the scalar path's
simulate_one, or every call into the library (the batch in lanes switches stacks, which hides
simulate_one's calls from callgrind; callgrind runs no AVX-512)::

    ROCKING_LANES=0 valgrind --tool=callgrind --collect-atstart=no --toggle-collect=simulate_one \
        --callgrind-out-file=cg.stops python bench/stops_map.py stops -n 20
    valgrind --tool=callgrind --collect-atstart=no --toggle-collect=_ctypes_callproc \
        --callgrind-out-file=cg.stops python bench/stops_map.py stops -n 20
    callgrind_annotate cg.stops | head      # the total, divided by the responses

or, with ``--time``, the CPU time of the stops' map over the free one in paired runs (median of
``--pairs``), the batch's lanes on and off (``ROCKING_LANES=0`` in the environment also turns them off);
with ``--split`` too, the same over the map's cases where the mass never reaches a pad (the same motion
as the free guide's: the stops' bookkeeping alone) and over those where it does, with their impacts::

    python bench/stops_map.py stops --time [--split]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from rocking import Block, Damper, Stops
from rocking.sim.cases import pulse_cases, run_cases


def cases(kind: str, n: int, pick: np.ndarray | None = None, law: str = "kelvin-voigt"):
    """The block and the map's cases of ``kind`` ("free" or "stops"), those of the mask ``pick`` over its
    ``n * n`` cells (in the order of the results) if given; ``law``: the pads' (``Stops.at_edges``' defaults)."""
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    Omega, beta = np.meshgrid(np.linspace(1, 10, n), np.linspace(1, 10, n), indexing="ij")
    if pick is not None:
        Omega, beta = Omega.ravel()[pick], beta.ravel()[pick]
    params = damper.as_params()
    if kind == "stops":
        params = {**params, **Stops.at_edges(block, damper, law=law).as_params()}
    models = {"free": "omd", "kelvin-voigt": "omd_stops", "hunt-crossley": "omd_stops_hc"}
    model = models[law if kind == "stops" else kind]
    return block, pulse_cases(block, Omega, beta, model=model, params=params, rtol=1e-8)


def paired_ratio(n: int, pairs: int, lanes: bool, pick: np.ndarray | None = None) -> tuple[float, dict, dict]:
    """The median over ``pairs`` paired runs of the stops' map's CPU time over the free one's (C path, one thread),
    and the results of both maps (those of the last run); ``pick`` as in :func:`cases`."""
    _, free = cases("free", n, pick)
    _, stopped = cases("stops", n, pick)
    for kind in ("free", "stops"):  # build and load outside the timing
        run_cases(cases(kind, 1)[1], "c", 1, lanes)
    ratios, res_free, res = [], {}, {}
    for _ in range(pairs):
        start = time.process_time()
        res_free = run_cases(free, "c", 1, lanes)
        middle = time.process_time()
        res = run_cases(stopped, "c", 1, lanes)
        ratios.append((time.process_time() - middle) / (middle - start))
    return float(np.median(ratios)), res_free, res


def print_ratios(n: int, pairs: int, pick: np.ndarray | None = None, label: str = "") -> None:
    """The ratios of :func:`paired_ratio`, lanes on and off, with the impacts of both maps."""
    for lanes in (True, False):
        ratio, free, stops = paired_ratio(n, pairs, lanes, pick)
        print(
            f"stops over free{label}, lanes {'on' if lanes else 'off'}: {ratio:.3f}x CPU (median of {pairs} pairs; "
            f"{len(stops['impacts'])} responses, impacts {int(free['impacts'].sum())} free, "
            f"{int(stops['impacts'].sum())} stops)"
        )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kind", choices=["free", "stops"])
    parser.add_argument("-n", type=int, default=50, help="grid size per axis (default 50)")
    parser.add_argument("--time", action="store_true", help="the CPU time over the free map's, lanes on and off")
    parser.add_argument("--pairs", type=int, default=5, help="paired runs of --time (default 5)")
    parser.add_argument("--split", action="store_true", help="--time also over the cases without and with a contact")
    parser.add_argument(
        "--law", choices=["kelvin-voigt", "hunt-crossley"], default="kelvin-voigt", help="the pads' law (stops' map)"
    )
    args = parser.parse_args(argv)
    if args.time:
        print_ratios(args.n, args.pairs)
        if args.split:
            touch = run_cases(cases("stops", args.n)[1], "c", 1)["stop_contacts"] > 0
            print_ratios(args.n, args.pairs, ~touch, " where the mass reaches no pad")
            print_ratios(args.n, args.pairs, touch, " where it does")
        return 0
    block, batch = cases(args.kind, args.n, law=args.law)
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
