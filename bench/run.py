"""`make bench`: speed of the simulator and of the studies, measured in one run.

Cases: the 50 x 50 map of issue 3 (Omega and beta in [1, 10], the reference block
of docs/model.md section 9, a damper with gamma = 0.05, omega_m = p, zeta = 0.05,
rtol = 1e-8, each response followed until overturning, rest, or 15 s after the
pulse). The C path runs the whole map; the NumPy path and the baseline (SymPy
lambdify + solve_ivp, bench/baseline.py) run the same random subset of it.
Figures are ratios measured in this run: the machine is shared and noisy. The instructions per
response of the C path on the same map under callgrind (bench/instructions.py) do not depend on
the load: a change to sim.c is judged by them.

The record bench: a 20 s synthetic record sampled at 0.005 s (4,000 intervals: band-passed
noise from a fixed seed under a trapezoidal envelope, peak 0.3 g) on the same block and damper
at 50 scales (an incremental dynamic analysis), C against the baseline with ``np.interp``.
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
import split  # noqa: E402
from bench_map import GAMMA, H_MASS, OMEGA_RATIO, ZETA, map_cases  # noqa: E402
from machine import machine  # noqa: E402

from rocking import Block, SampledMotion  # noqa: E402
from rocking.sim import c_backend  # noqa: E402
from rocking.sim.cases import pulse_cases, run_cases, sampled_cases  # noqa: E402

#: Stochastic motions of the fragility whose CPU is split (bench/split.py).
SPLIT_MOTIONS = 200


def timed(fn, *args, **kw):
    start = time.perf_counter()
    out = fn(*args, **kw)
    return out, time.perf_counter() - start


def cpu_timed(fn, *args, **kw):
    """Result, wall seconds and CPU seconds of this process (time stolen by neighbours excluded)."""
    cpu = time.process_time()
    out, wall = timed(fn, *args, **kw)
    return out, wall, time.process_time() - cpu


def bench_simulator(n_grid: int, n_subset: int, seed: int) -> dict:
    block, Omega, beta, cases = map_cases(n_grid)
    run_cases(pulse_cases(block, [2.0], [2.0], gamma=GAMMA, h=H_MASS), "c")  # build and load outside the timing
    # Best of three: the machine is shared, and the slowest runs measure the neighbours.
    runs = [cpu_timed(run_cases, cases, "c", 1) for _ in range(3)]
    c_res, c_time, c_cpu = min(runs, key=lambda r: r[1])
    # The scalar path of the same batch (the lanes off), in turn with it: the lanes' gain in one run.
    scalar_cpu = min(cpu_timed(run_cases, cases, "c", 1, False)[2] for _ in range(3))
    n = len(cases)
    pick = np.random.default_rng(seed).choice(n, size=n_subset, replace=False)
    from rocking.sim import numpy_backend

    np_over, np_time = [], 0.0
    for i in pick:
        r, dt = timed(numpy_backend.simulate, cases.problem(i))
        np_over.append(r.overturned)
        np_time += dt
    funcs, t_lambdify = timed(baseline.build_functions)
    base_over, base_time = [], 0.0
    for i in pick:
        params = tuple(cases.p[i])
        pulse = cases.settings["a_g"][i], cases.settings["omega_g"][i]
        (over, _), dt = timed(baseline.simulate, funcs, params, *pulse)
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
        "c_responses_per_cpu_s": n / c_cpu,
        "c_lanes": c_backend.lanes(cases.model),
        "c_scalar_responses_per_cpu_s": n / scalar_cpu,
        "c_scalar_over_lanes_cpu": scalar_cpu / c_cpu,
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


def record_motion(seed: int = 2026, duration: float = 20.0, dt: float = 0.005, pga_g: float = 0.3) -> SampledMotion:
    """The bench record: white noise band-passed to 0.5 - 5 Hz (Butterworth, order 4) under an envelope
    rising over 2 s, strong for 8 s and decaying to 20 s, scaled to a peak of ``pga_g`` g."""
    from scipy.signal import butter, sosfilt

    t = np.arange(int(round(duration / dt)) + 1) * dt
    noise = np.random.default_rng(seed).standard_normal(t.size)
    band = sosfilt(butter(4, [0.5, 5.0], btype="bandpass", fs=1 / dt, output="sos"), noise)
    envelope = np.clip(t / 2.0, 0, 1) * np.where(t < 10.0, 1.0, np.exp(-(t - 10.0) / 3.0))
    return SampledMotion(band * envelope, dt=dt).scaled_to_pga(pga_g * 9.81)


def bench_record(n_scales: int, n_baseline: int) -> dict:
    """An IDA of the bench record: C responses per second per core over ``n_scales`` scales (0.1 - 2.5 of
    the record), and the baseline on ``n_baseline`` of them."""
    block = Block.reference()
    motion = record_motion()
    scales = np.linspace(0.1, 2.5, n_scales)
    cases = sampled_cases(block, motion, scales, gamma=GAMMA, omega_ratio=OMEGA_RATIO, zeta=ZETA, h=H_MASS)
    run_cases(sampled_cases(block, motion, [0.1], gamma=GAMMA, h=H_MASS, t_after=0.1), "c")  # build and load first
    runs = [cpu_timed(run_cases, cases, "c", 1) for _ in range(3)]
    c_res, c_time, c_cpu = min(runs, key=lambda r: r[1])
    funcs = baseline.build_functions()
    pick = np.linspace(0, n_scales - 1, n_baseline).astype(int)
    base_over, base_time = [], 0.0
    for i in pick:
        (over, _), dt = timed(
            baseline.simulate_record, funcs, tuple(cases.p[i]), motion.a, motion.dt, motion.scale * scales[i]
        )
        base_over.append(over)
        base_time += dt
    c_per, base_per = c_time / len(cases), base_time / n_baseline
    return {
        "record": f"{motion.t_p:g} s at {motion.dt:g} s ({motion.n} samples), peak {motion.pga / 9.81:.2f} g",
        "responses": len(cases),
        "c_responses_per_s_per_core": len(cases) / c_time,
        "c_responses_per_cpu_s": len(cases) / c_cpu,
        "c_ms_per_response": 1e3 * c_per,
        "baseline_ms_per_response": 1e3 * base_per,
        "speedup_c_vs_baseline": base_per / c_per,
        "baseline_subset": int(n_baseline),
        "verdicts_c_eq_baseline": int(np.sum(c_res["overturned"][pick] == np.array(base_over))),
        "overturned_fraction": float(np.mean(c_res["overturned"])),
    }


def bench_stops(n_grid: int, pairs: int = 3) -> dict:
    """The bench map with stops at the block's edges against the unlimited damper: the median CPU time ratio of
    paired runs (C path, one thread), the batch's lanes on (the default) and off (bench/stops_map.py --time)."""
    import stops_map

    block = stops_map.cases("free", 1)[0]
    ratio, _, res = stops_map.paired_ratio(n_grid, pairs, lanes=True)
    scalar, _, _ = stops_map.paired_ratio(n_grid, pairs, lanes=False)
    return {
        "stops_over_free_time": ratio,
        "stops_over_free_time_scalar": scalar,
        "stop_contacts_per_response": int(res["stop_contacts"].sum()) / len(res["stop_contacts"]),
        "stroke_past_edges_with_stops": int((res["x_max"] > block.B / 2).sum()),
    }


def _map(n: int, workers: int, runs: str):
    """A full bare + damper overturning map of ``n x n``, both directions, on fresh tiles; (study, seconds).

    Every cell (``full=True``): the throughput and memory of the tiles, comparable across versions; the adaptive
    map has its own bench (bench/adaptive.py)."""
    from rocking.study.config import Grid, Setting, Tuning
    from rocking.study.overturning_map import overturning_map
    from rocking.study.tiles import Execution

    setting = Setting(Block.reference())
    tuning = Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS)
    grid_o, grid_b = Grid("Omega", 1.0, 10.0, n), Grid("beta", 1.0, 10.0, n)
    execution = Execution(workers=workers, progress=False)
    return timed(overturning_map, setting, tuning, grid_o, grid_b, execution, runs=runs, full=True)


def _fragility(n: int, runs: str):
    """A fragility study over ``n`` short stochastic motions (10 s at 0.01 s), 4 PGA levels, both directions."""
    from rocking.model.stochastic import SiteModel
    from rocking.study.config import Grid, Setting, Tuning
    from rocking.study.ida import incremental_dynamic_analysis
    from rocking.study.suite import Suite
    from rocking.study.tiles import Execution

    site = SiteModel(arias=0.3, d595=4.0, t_mid=3.0, f_mid=4.0, f_slope=-0.1, zeta_f=0.25, dt=0.01, duration=10.0)
    return timed(
        incremental_dynamic_analysis,
        Setting(Block.reference(), t_after=5.0),
        Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS),
        Suite.stochastic(site, n, seed=1),
        Grid("pga", 1.0, 8.0, 4),
        Execution(workers=2, progress=False),
        measure_name="pga",
        runs=runs,
    )


def bench_studies(n_map: int, n_memory: int) -> dict:
    """Map throughput with 1 and 2 local workers; memory of a large map; the wall time of the demo and of
    ``rocking threshold`` on its default grid."""
    import subprocess
    import tempfile

    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        # Best of three interleaved runs each: the machine is shared. Each run is a whole study,
        # as a user waits for it (on the C back end the 2 workers are threads: no pool start-up).
        for repeat in range(3):
            for workers in (1, 2):
                cpu = time.process_time()
                study, seconds = _map(n_map, workers, f"{tmp}/runs{repeat}{workers}")
                key = f"map_responses_per_s_{workers}_workers"
                if study.run["responses"] / seconds > out.get(key, 0.0):
                    out[key] = study.run["responses"] / seconds
                    # CPU seconds per second of the best run: below the workers, the machine's other load took cores.
                    out[f"map_cpus_{workers}_workers"] = (time.process_time() - cpu) / seconds
        out["map_speedup_2_vs_1"] = out["map_responses_per_s_2_workers"] / out["map_responses_per_s_1_workers"]
        # Where a study's CPU goes on one worker: in C, drawing motions, or in the Python around them.
        out["split_map"] = split.map_split(n_map)
        out["split_fragility"] = split.fragility_split(SPLIT_MOTIONS)
        # Peak memory in a fresh process per size: it must not grow with the grid beyond the result arrays.
        probe = (
            "import resource, sys; sys.path.insert(0, {here!r}); import run; "
            "study, _ = run._map({n}, 2, {runs!r}); "
            "size = study.data.nbytes; "
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, size)"
        )
        for n in (n_memory // 4, n_memory):
            code = probe.format(here=os.path.dirname(os.path.abspath(__file__)), n=n, runs=f"{tmp}/mem{n}")
            rss, size = map(
                int,
                subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split(),
            )
            out[f"map_{n}x{n}_peak_rss_mb"] = rss / 2**20
            out[f"map_{n}x{n}_result_arrays_mb"] = size / 2**20
        fragility = probe.replace("run._map({n}, 2, {runs!r})", "run._fragility({n}, {runs!r})")
        for n in (100, 1000):  # the suite is made in the tiles: memory must not grow with the motions
            code = fragility.format(here=os.path.dirname(os.path.abspath(__file__)), n=n, runs=f"{tmp}/frag{n}")
            start = time.perf_counter()
            rss, size = map(
                int,
                subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split(),
            )
            out[f"fragility_{n}_seconds"] = time.perf_counter() - start
            out[f"fragility_{n}_peak_rss_mb"] = rss / 2**20
            out[f"fragility_{n}_result_arrays_mb"] = size / 2**20
        for command in ("demo", "threshold"):  # threshold: its default grid, on 2 local workers
            start = time.perf_counter()
            run = [sys.executable, "-m", "rocking.cli.main", command, "--out", f"{tmp}/{command}", "--no-progress"]
            workers = ["--workers", "2"] if command == "threshold" else []
            subprocess.run(run + workers, check=True, capture_output=True)
            out[f"{command}_seconds"] = time.perf_counter() - start
    out["n_map"], out["n_memory"] = n_map, n_memory
    return out


def bench_overhead(calls: int = 2000, repeats: int = 5) -> dict:
    """The Python of one ``rocking.simulate`` call around its C run: the reference block, damper and a pulse of
    beta = 3, Omega = 4; the whole call and the time inside the C entry point, best of ``repeats``.

    Measured twice: with the same block and damper objects call after call (a loop over pulses: their check
    against each other is remembered), and with two equal dampers in turn (checked at every call).
    """
    import rocking
    from rocking.sim import c_backend

    block = Block.reference()
    dampers = [
        rocking.Damper.from_nondim(block, gamma=GAMMA, omega_ratio=OMEGA_RATIO, zeta=ZETA, h=H_MASS) for _ in range(2)
    ]
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
    rocking.simulate(block, dampers[0], pulse)
    lib = c_backend.library("omd").lib
    entry, inside = lib.rocking_simulate, [0.0]

    def timed(*args):
        start = time.perf_counter()
        try:
            return entry(*args)
        finally:
            inside[0] += time.perf_counter() - start

    def best(turn: list) -> tuple[float, float, float]:
        runs = []
        for _ in range(repeats):
            inside[0] = 0.0
            start = time.perf_counter()
            for i in range(calls):
                rocking.simulate(block, turn[i % len(turn)], pulse)
            whole = time.perf_counter() - start
            runs.append(((whole - inside[0]) / calls * 1e6, inside[0] / calls * 1e6, whole / calls * 1e6))
        return min(runs)

    lib.rocking_simulate = timed
    try:
        overhead, c_us, whole_us = best(dampers[:1])
        overhead_new_damper = best(dampers)[0]
    finally:
        lib.rocking_simulate = entry
    return {
        "calls": calls,
        "overhead_us": overhead,
        "c_us": c_us,
        "whole_us": whole_us,
        "overhead_another_damper_us": overhead_new_damper,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=50)
    parser.add_argument("--subset", type=int, default=30, help="cases run on the NumPy path and the baseline")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--map-grid", type=int, default=200, help="side of the map timed with 1 and 2 workers")
    parser.add_argument("--memory-grid", type=int, default=400, help="side of the map whose peak memory is measured")
    parser.add_argument("--record-scales", type=int, default=50, help="scales of the record bench (C path)")
    parser.add_argument("--record-subset", type=int, default=6, help="scales of the record run on the baseline")
    parser.add_argument("--json", help="also write the figures to this file")
    parser.add_argument("--no-studies", action="store_true", help="only the simulator")
    parser.add_argument("--no-instructions", action="store_true", help="skip the callgrind count of the bench map")
    args = parser.parse_args(argv)
    results = {"machine": machine(), "simulator": bench_simulator(args.grid, args.subset, args.seed)}
    sim = results["simulator"]
    print(f"simulator, {sim['map']} map at rtol 1e-8 ({sim['responses']} responses, ", end="")
    print(f"{sim['overturned_fraction']:.0%} overturn):")
    print(f"  C path        {sim['c_responses_per_s_per_core']:10.0f} responses/s/core  (target >= 10,000); ", end="")
    print(f"{sim['c_responses_per_cpu_s']:.0f} per CPU second, in lanes of {sim['c_lanes']} doubles per vector")
    print(f"  C scalar      {sim['c_scalar_responses_per_cpu_s']:10.0f} per CPU second: the lanes take ", end="")
    print(f"{sim['c_scalar_over_lanes_cpu']:.2f}x fewer CPU seconds per response (target with AVX2 >= 2.5)")
    print(f"  NumPy path    {sim['numpy_ms_per_response']:10.2f} ms/response   ", end="")
    print(f"C is {sim['speedup_c_vs_numpy']:.0f}x faster")
    print(f"  baseline      {sim['baseline_ms_per_response']:10.2f} ms/response   ", end="")
    print(f"C is {sim['speedup_c_vs_baseline']:.0f}x faster (target >= 300)")
    print(f"  verdicts on {sim['subset']} cases: C = NumPy {sim['verdicts_c_eq_numpy']}, ", end="")
    print(f"C = baseline {sim['verdicts_c_eq_baseline']}")
    if not args.no_instructions:
        import instructions

        results["instructions"] = instructions.measure(args.grid)
        print(instructions.line(results["instructions"]))
        results["instructions_lanes"] = instructions.measure(args.grid, lanes=True)
        print(instructions.line(results["instructions_lanes"]))
    rec = results["record"] = bench_record(args.record_scales, args.record_subset)
    print(f"record, {rec['record']}, {rec['responses']} scales ({rec['overturned_fraction']:.0%} overturn):")
    print(f"  C path        {rec['c_responses_per_s_per_core']:10.0f} responses/s/core  ", end="")
    print(f"({rec['c_ms_per_response']:.2f} ms/response)")
    print(f"  baseline      {rec['baseline_ms_per_response']:10.2f} ms/response   ", end="")
    print(f"C is {rec['speedup_c_vs_baseline']:.0f}x faster (target >= 300); ", end="")
    print(f"verdicts C = baseline on {rec['verdicts_c_eq_baseline']} of {rec['baseline_subset']}")
    over = results["overhead"] = bench_overhead()
    print(
        f"one rocking.simulate call: {over['overhead_us']:.0f} us of Python around {over['c_us']:.0f} us of C "
        f"(target <= 50 us; best of 5 x {over['calls']}); {over['overhead_another_damper_us']:.0f} us with "
        "another damper object at every call"
    )
    stops = results["stops"] = bench_stops(args.grid)
    print(
        f"  stops at the edges: {stops['stops_over_free_time']:.2f}x the CPU time per response of the unlimited damper "
        f"in lanes (target <= 1.5), {stops['stops_over_free_time_scalar']:.2f}x scalar (medians of 3 paired runs), "
        f"{stops['stop_contacts_per_response']:.1f} contacts per response"
    )
    if not args.no_studies:
        st = results["studies"] = bench_studies(args.map_grid, args.memory_grid)
        n, m = st["n_map"], st["n_memory"]
        print(f"studies, {n}x{n} map (block alone + damper):")
        print(
            f"  1 worker      {st['map_responses_per_s_1_workers']:10.0f} responses/s   "
            f"({st['map_cpus_1_workers']:.2f} CPUs used)"
        )
        print(
            f"  2 workers     {st['map_responses_per_s_2_workers']:10.0f} responses/s   "
            f"{st['map_speedup_2_vs_1']:.2f}x (target >= 1.85; {st['map_cpus_2_workers']:.2f} CPUs used)"
        )
        for side in (m // 4, m):
            print(
                f"  {side}x{side} map: peak memory {st[f'map_{side}x{side}_peak_rss_mb']:.0f} MB, "
                f"result arrays {st[f'map_{side}x{side}_result_arrays_mb']:.1f} MB"
            )
        for n in (100, 1000):
            rss, size, seconds = (st[f"fragility_{n}_{k}"] for k in ("peak_rss_mb", "result_arrays_mb", "seconds"))
            print(
                f"  fragility, {n} stochastic motions x 4 PGA levels x 2 directions x 2 parts: peak memory "
                f"{rss:.0f} MB, result arrays {size:.1f} MB, {seconds:.0f} s"
            )
        side = st["split_map"]["n"]
        print(f"  {split.describe(f'{side}x{side} map, 1 worker', st['split_map'])}")
        print(f"  {split.describe(f'fragility of {SPLIT_MOTIONS} motions, 1 worker', st['split_fragility'])}")
        print(f"  rocking demo  {st['demo_seconds']:10.1f} s")
        print(f"  rocking threshold {st['threshold_seconds']:6.1f} s (default grid, 2 workers)")
    results["machine"]["load_average_1min_after"] = os.getloadavg()[0]
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
