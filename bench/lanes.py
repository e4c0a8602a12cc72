"""The C batch in lanes against its scalar path (issue 40): CPU per response, and every difference of results.

On the maps of issue 40, each 50 x 50 by default (Omega and beta in [1, 10], the reference block and damper,
rtol = 1e-8): the bench map (bench/bench_map.py), the same damper with its stops at the block's edges (model
omd_stops, bench/stops_map.py) and the bench map without the early verdict. Each is run on the scalar path
(``lanes=False``) and in lanes at every vector width this CPU has (``ROCKING_LANES_ISA``: AVX-512F 8 doubles per
vector, AVX2 4, SSE2 2), in turn, one thread; the CPU time of each is the best of ``--repeat`` passes
(:func:`time.process_time` around the batch call, the case set-up outside). Printed per map and width: the CPU
microseconds per response, the ratio scalar / lanes, the cases whose status, verdict, impacts, uplifts or stop
contacts differ (issue 40: 0), the largest relative difference of theta_max and x_max (issue 40: <= 1e-7)::

    python bench/lanes.py                 # the three maps, 50 x 50: about a minute
    python bench/lanes.py -n 20 --maps bench --json bench/lanes.json
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_map import map_cases  # noqa: E402
from machine import command_line, ended, machine  # noqa: E402
from stops_map import cases as stops_cases  # noqa: E402

from rocking.sim import c_backend  # noqa: E402
from rocking.sim.cases import Cases, run_cases  # noqa: E402

#: The discrete results, identical on both paths (issue 40).
DISCRETE = ("status", "overturned", "impacts", "uplifts", "stop_contacts", "slides")
#: The vector widths by ROCKING_LANES_ISA, widest first (AVX2 is the default where the CPU has it, AVX-512F on
#: request: rocking/sim/csrc/lanes.h).
ISAS = {"avx512": "avx512", "avx2": "avx2", "sse2": "sse2"}


def maps(n: int) -> dict[str, Cases]:
    """The maps of issue 40, ``n x n`` each."""
    bench = map_cases(n)[-1]
    return {
        "bench": bench,
        "stops": stops_cases("stops", n)[1],
        "early-verdict-off": Cases(bench.model, bench.p, {**bench.settings, "early_verdict": False}),
    }


def widths(model: str) -> dict[str, int]:
    """The widths this CPU runs, by name: each ROCKING_LANES_ISA cap and the width it gives, duplicates dropped."""
    found: dict[str, int] = {}
    for name, isa in ISAS.items():
        os.environ["ROCKING_LANES_ISA"] = isa
        width = c_backend.lanes(model)
        if width and width not in found.values():
            found[name] = width
    os.environ.pop("ROCKING_LANES_ISA")
    return found


def cpu(cases: Cases, lanes: bool, repeat: int) -> tuple[dict, float]:
    """The results of one pass and the least CPU seconds of ``repeat`` passes."""
    best = float("inf")
    for _ in range(repeat):
        start = time.process_time()
        out = run_cases(cases, "c", 1, lanes)
        best = min(best, time.process_time() - start)
    return out, best


def differences(lanes: dict, scalar: dict) -> dict:
    """The cases whose discrete results differ, and the largest relative difference of theta_max and x_max."""
    discrete = sum(int(np.sum(lanes[k] != scalar[k])) for k in DISCRETE)
    worst = {}
    for name in ("theta_max", "x_max"):
        a, b = lanes[name], scalar[name]
        rel = np.abs(a - b) / np.maximum(np.abs(b), np.finfo(float).tiny)
        worst[name] = float(np.nanmax(rel)) if np.any(np.isfinite(rel)) else 0.0
    return {"discrete_differences": discrete, "theta_max_rel": worst["theta_max"], "x_max_rel": worst["x_max"]}


def measure(n: int, names: list[str], repeat: int) -> dict:
    results: dict = {"machine": machine(), "command": command_line("lanes.py", None), "grid": n, "maps": {}}
    for name, cases in maps(n).items():
        if name not in names:
            continue
        run_cases(cases, "c", 1)  # the library built and loaded outside the timing
        scalar, scalar_cpu = cpu(cases, False, repeat)
        row = {"responses": len(cases), "scalar_us": 1e6 * scalar_cpu / len(cases), "lanes": {}}
        for isa_name, width in widths(cases.model.name).items():
            os.environ["ROCKING_LANES_ISA"] = ISAS[isa_name]
            out, lanes_cpu = cpu(cases, True, repeat)
            os.environ.pop("ROCKING_LANES_ISA")
            row["lanes"][isa_name] = {
                "width": width,
                "lanes_us": 1e6 * lanes_cpu / len(cases),
                "ratio": scalar_cpu / lanes_cpu,
                **differences(out, scalar),
            }
        results["maps"][name] = row
    results.update(ended())
    return results


def lines(results: dict) -> list[str]:
    out = []
    for name, row in results["maps"].items():
        out.append(f"{name} map {results['grid']}x{results['grid']}: scalar {row['scalar_us']:.1f} us CPU per response")
        for isa, r in row["lanes"].items():
            out.append(
                f"  lanes {isa} ({r['width']} per vector): {r['lanes_us']:.1f} us, scalar/lanes {r['ratio']:.2f}x; "
                f"discrete differences {r['discrete_differences']}, theta_max {r['theta_max_rel']:.1e}, "
                f"x_max {r['x_max_rel']:.1e} relative"
            )
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=50, help="grid size per axis (default 50)")
    parser.add_argument("--maps", nargs="+", default=["bench", "stops", "early-verdict-off"], help="maps to run")
    parser.add_argument("--repeat", type=int, default=3, help="passes per path, the least CPU kept (default 3)")
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    results = measure(args.n, args.maps, args.repeat)
    print("\n".join(lines(results)))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
