"""`make bench`: speed of the simulator and of the studies, measured in one run.

Cases: the 50 x 50 map of issue 3 (Omega and beta in [1, 10], the reference block
of model.md section 9, a damper with gamma = 0.05, omega_m = p, zeta = 0.05,
rtol = 1e-8, each response followed until overturning, rest, or 15 s after the
pulse). The C path runs the whole map; the NumPy path and the baseline (SymPy
lambdify + solve_ivp, bench/baseline.py) run the same random subset of it.
Figures are ratios measured in this run: the machine is shared and noisy.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))

import baseline  # noqa: E402

from rocking import Block  # noqa: E402
from rocking.batch import pulse_cases, run_cases  # noqa: E402

GAMMA, OMEGA_RATIO, ZETA, H_MASS = 0.05, 1.0, 0.05, 0.05


def map_cases(n: int):
    block = Block.reference()
    Omega, beta = np.meshgrid(np.linspace(1, 10, n), np.linspace(1, 10, n), indexing="ij")
    cases = pulse_cases(block, Omega, beta, gamma=GAMMA, omega_ratio=OMEGA_RATIO, zeta=ZETA, h=H_MASS, rtol=1e-8)
    return block, Omega.ravel(), beta.ravel(), cases


def timed(fn, *args, **kw):
    start = time.perf_counter()
    out = fn(*args, **kw)
    return out, time.perf_counter() - start


def bench_simulator(n_grid: int, n_subset: int, seed: int) -> dict:
    block, Omega, beta, cases = map_cases(n_grid)
    run_cases(pulse_cases(block, [2.0], [2.0], gamma=GAMMA, h=H_MASS), "c")  # build and load outside the timing
    c_res, c_time = timed(run_cases, cases, "c", 1)
    n = len(cases)
    pick = np.random.default_rng(seed).choice(n, size=n_subset, replace=False)
    from rocking import numpy_backend

    np_over, np_time = [], 0.0
    for i in pick:
        r, dt = timed(numpy_backend.simulate, cases.problem(i))
        np_over.append(r.overturned)
        np_time += dt
    funcs, t_lambdify = timed(baseline.build_functions)
    base_over, base_time = [], 0.0
    for i in pick:
        params = tuple(cases.p[i])
        (over, _), dt = timed(baseline.simulate, funcs, params, cases.a_g[i], cases.omega_g[i])
        base_over.append(over)
        base_time += dt
    c_per = c_time / n
    np_per = np_time / n_subset
    base_per = base_time / n_subset
    return {
        "map": f"{n_grid}x{n_grid}",
        "responses": n,
        "c_seconds": c_time,
        "c_responses_per_s_per_core": n / c_time,
        "numpy_ms_per_response": 1e3 * np_per,
        "baseline_ms_per_response": 1e3 * base_per,
        "baseline_lambdify_s": t_lambdify,
        "speedup_c_vs_numpy": np_per / c_per,
        "speedup_c_vs_baseline": base_per / c_per,
        "subset": int(n_subset),
        "verdicts_c_eq_numpy": int(np.sum(c_res["overturned"][pick] == np.array(np_over))),
        "verdicts_c_eq_baseline": int(np.sum(c_res["overturned"][pick] == np.array(base_over))),
        "overturned_fraction": float(np.mean(c_res["overturned"])),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=50)
    parser.add_argument("--subset", type=int, default=30, help="cases run on the NumPy path and the baseline")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    results = {"simulator": bench_simulator(args.grid, args.subset, args.seed)}
    sim = results["simulator"]
    print(
        f"simulator, {sim['map']} map at rtol 1e-8 ({sim['responses']} responses, {sim['overturned_fraction']:.0%} overturn):"
    )
    print(f"  C path        {sim['c_responses_per_s_per_core']:10.0f} responses/s/core  (target >= 10,000)")
    print(
        f"  NumPy path    {sim['numpy_ms_per_response']:10.2f} ms/response   C is {sim['speedup_c_vs_numpy']:.0f}x faster"
    )
    print(
        f"  baseline      {sim['baseline_ms_per_response']:10.2f} ms/response   C is {sim['speedup_c_vs_baseline']:.0f}x faster"
        " (target >= 300)"
    )
    print(
        f"  verdicts on {sim['subset']} cases: C = NumPy {sim['verdicts_c_eq_numpy']}, C = baseline {sim['verdicts_c_eq_baseline']}"
    )
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
